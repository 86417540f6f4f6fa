//! The syntax tree of a `.lamp` file: what was written, with spans, before any checking.

use crate::source::Span;

/// A name as written.
#[derive(Clone, Debug)]
pub struct Name {
    pub text: String,
    pub span: Span,
}

/// A string literal (its contents, without quotes).
#[derive(Clone, Debug)]
pub struct Text {
    pub text: String,
    pub span: Span,
}

/// A unit suffix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    Metre,
    Centimetre,
    Millimetre,
    Degree,
    Radian,
    Second,
    Millisecond,
    Hertz,
}

/// A number with an optional unit.
#[derive(Clone, Debug)]
pub struct Quantity {
    pub value: f64,
    pub unit: Option<(Unit, Span)>,
    pub span: Span,
}

/// `(a, b, c) unit?`
#[derive(Clone, Debug)]
pub struct Vector {
    pub values: [f64; 3],
    pub number_spans: [Span; 3],
    pub unit: Option<(Unit, Span)>,
    pub span: Span,
}

/// `(x, y, z) m rpy (r, p, y) deg`
#[derive(Clone, Debug)]
pub struct Pose {
    pub position: Vector,
    pub rotation: Option<Vector>,
    pub span: Span,
}

/// An option value.
#[derive(Clone, Debug)]
pub enum Value {
    Text(Text),
    Quantity(Quantity),
    Word(Name),
}

/// `key value`
#[derive(Clone, Debug)]
pub struct OptionEntry {
    pub key: Name,
    pub value: Value,
}

/// `noise D A` in a `simulate` block: the keyword (as a name, for duplicate reports), the
/// distance and the angle.
#[derive(Clone, Debug)]
pub struct NoiseEntry {
    pub keyword: Name,
    pub distance: Quantity,
    pub angle: Quantity,
}

/// A top-level declaration; `span` covers its keyword.
// A spec has a few dozen items, built once: boxing the large variants would buy nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Item {
    Domain(Name),
    Seed { value: Quantity, span: Span },
    Robot(Robot),
    Type(TypeDecl),
    Demonstrations { sources: Vec<DemoSource> },
    Learn { items: Vec<LearnItem>, span: Span },
    Relation(Relation),
    Structure(Structure),
    Problem(Problem),
    Plugins { plugins: Vec<Plugin> },
}

#[derive(Clone, Debug)]
pub struct Robot {
    pub name: Name,
    pub items: Vec<(RobotItem, Span)>,
}

#[derive(Clone, Debug)]
pub enum RobotItem {
    Urdf(Text),
    Kind(Name),
    Mount(Pose),
    Part { name: Name, link: Text },
    Grab { min: Quantity, max: Quantity },
    Group { name: Name, joints: Vec<Text> },
    Config { name: Name, values: Vec<(Name, Quantity)> },
    IgnoreCollision(Text, Text),
}

#[derive(Clone, Debug)]
pub struct TypeDecl {
    pub name: Name,
    pub items: Vec<(TypeItem, Span)>,
}

#[derive(Clone, Debug)]
pub enum TypeItem {
    Mobility(Name),
    World,
    Box { size: Vector, at: Option<Pose> },
    Cylinder { radius: Quantity, height: Quantity, at: Option<Pose> },
    Sphere { radius: Quantity, at: Option<Pose> },
    Mesh { path: Text, mode: Option<Name>, at: Option<Pose> },
}

#[derive(Clone, Debug)]
pub enum DemoSource {
    Simulate {
        demonstrator: Name,
        options: Vec<OptionEntry>,
        /// Every `noise D A` of the block (more than one is reported).
        noise: Vec<NoiseEntry>,
    },
    Files(Text),
    /// `files "PATTERN" as ros2 { … }`: bags of standard messages with a frame mapping.
    Ros2 {
        pattern: Text,
        objects: Vec<Ros2Object>,
        robots: Vec<Ros2Robot>,
    },
}

/// `object TYPE NAME frame "FRAME"` in a `ros2` mapping; the frame defaults to the name.
#[derive(Clone, Debug)]
pub struct Ros2Object {
    pub type_name: Name,
    pub name: Name,
    pub frame: Option<Text>,
}

/// `robot NAME frame "FRAME" held topic "TOPIC"` or `… grasp joint "JOINT" below VALUE` in a
/// `ros2` mapping.
#[derive(Clone, Debug)]
pub struct Ros2Robot {
    pub robot: Name,
    pub frame: Text,
    pub held_topic: Option<Text>,
    /// The gripper joint and the value below which it is closed; the span covers the clause.
    pub grasp_joint: Option<(Text, Quantity, Span)>,
}

#[derive(Clone, Debug)]
pub enum LearnItem {
    Threshold(Quantity, Span),
    Position {
        bins: Vector,
        range: Option<Vector>,
        span: Span,
    },
    Rotation(Quantity, Span),
    Components(Quantity, Span),
    Likelihood(Quantity, Span),
    /// `clear on|off|auto`: whether `clear_…` relations are invented.
    Clear(lamp_spec::Switch, Span),
    /// `nowhere on|off|auto`: whether `nowhere_…` relations are invented.
    Nowhere(lamp_spec::Switch, Span),
    /// `symmetry on|off|auto`: whether relative poses are compared up to the shapes' symmetries
    /// (the whole block's setting).
    Symmetry(lamp_spec::Switch, Span),
    Pair {
        first: Name,
        second: Name,
        items: Vec<LearnItem>,
        span: Span,
    },
    IgnorePair(Name, Name),
}

#[derive(Clone, Debug)]
pub struct Relation {
    pub name: Name,
    pub parameters: [Name; 2],
    pub secondary: Name,
    pub primary: Name,
    pub example: Pose,
}

#[derive(Clone, Debug)]
pub struct Structure {
    pub name: Name,
    pub placements: Vec<Placement>,
}

/// `TYPE OBJECT at POSE`
#[derive(Clone, Debug)]
pub struct Placement {
    pub type_name: Name,
    pub object: Name,
    pub pose: Pose,
}

#[derive(Clone, Debug)]
pub struct Problem {
    pub name: Name,
    pub items: Vec<ProblemItem>,
}

#[derive(Clone, Debug)]
pub enum ProblemItem {
    Scene { items: Vec<SceneItem>, span: Span },
    SceneFile(Text),
    Goal { items: Vec<GoalItem>, span: Span },
}

#[derive(Clone, Debug)]
pub enum SceneItem {
    Robot { name: Name, at: Option<Pose>, config: Option<Name> },
    Object(Placement),
}

#[derive(Clone, Debug)]
pub enum GoalItem {
    At { object: Name, pose: Pose, distance: Quantity, angle: Quantity },
    Structure { name: Name, anchor: Name, offset: Option<Pose>, span: Span },
    Atom { relation: Name, arguments: Vec<Name>, span: Span },
}

#[derive(Clone, Debug)]
pub enum PluginRef {
    Builtin(Name),
    Library(Text),
}

#[derive(Clone, Debug)]
pub struct Plugin {
    pub kind: Name,
    pub source: PluginRef,
    pub options: Vec<OptionEntry>,
    pub span: Span,
}
