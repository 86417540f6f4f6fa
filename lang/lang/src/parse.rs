//! pest → syntax tree. The pest types stay in this module.

use pest::Parser as _;
use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::Pair;

use crate::ast::*;
use crate::diagnostics::{Diagnostic, SpecError, at};
use crate::source::{FileId, Span};

#[derive(pest_derive::Parser)]
#[grammar = "lamp.pest"]
struct LampParser;

/// Parses a whole spec file.
pub(crate) fn parse_spec(file: FileId, text: &str) -> Result<Vec<Item>, Diagnostic> {
    // Track the furthest position reached and the tokens expected there, so that a syntax error
    // points at the offending word rather than at the start of the declaration around it.
    pest::set_error_detail(true);
    let mut pairs = LampParser::parse(Rule::spec, text).map_err(|e| syntax_error(file, text, e))?;
    let spec = pairs.next().expect("the spec rule always yields one pair");
    let lower = Lower { file };
    Ok(spec.into_inner().filter(|p| p.as_rule() != Rule::EOI).map(|p| lower.item(p)).collect())
}

/// Parses a scene file: a list of placements without the surrounding `scene { }`.
pub(crate) fn parse_scene_file(file: FileId, text: &str) -> Result<Vec<SceneItem>, Diagnostic> {
    let mut pairs =
        LampParser::parse(Rule::scene_file, text).map_err(|e| syntax_error(file, text, e))?;
    let scene = pairs.next().expect("the scene_file rule always yields one pair");
    let lower = Lower { file };
    Ok(scene
        .into_inner()
        .filter(|p| p.as_rule() != Rule::EOI)
        .map(|p| lower.scene_item(p))
        .collect())
}

fn syntax_error(file: FileId, text: &str, error: pest::error::Error<Rule>) -> Diagnostic {
    let (mut start, mut end) = match error.location {
        InputLocation::Pos(position) => (position, position),
        InputLocation::Span((start, end)) => (start, end),
    };
    let mut expected_words: Vec<String> = Vec::new();
    if let Some(attempts) = error.parse_attempts()
        && attempts.max_position > start
        && attempts.max_position <= text.len()
    {
        start = attempts.max_position;
        end = start;
        expected_words.extend(
            attempts
                .expected_tokens()
                .iter()
                .map(ToString::to_string)
                // Whitespace and comments may always come next; naming them helps nobody.
                .filter(|token| !token.trim().is_empty() && token != "//")
                .map(|token| format!("`{token}`")),
        );
        expected_words.extend(
            attempts.call_stacks().iter().filter_map(|stack| {
                stack.deepest.get_rule().map(|rule| describe(*rule).to_string())
            }),
        );
    }
    // Point at the whole offending token, at least its first character (which may be a
    // multi-byte space), so the label is readable and never splits a character.
    let rest = &text[start..];
    let first = rest.chars().next().map_or(0, char::len_utf8);
    let token_end = rest
        .find(|c: char| c.is_whitespace() || "(){},:".contains(c))
        .map_or(text.len(), |offset| start + offset.max(first));
    let end = end.max(token_end).min(text.len());
    let expected = match &error.variant {
        _ if !expected_words.is_empty() => join_alternatives(expected_words),
        ErrorVariant::ParsingError { positives, .. } => {
            let mut words: Vec<&str> = positives.iter().map(|rule| describe(*rule)).collect();
            words.sort_unstable();
            words.dedup();
            match words.as_slice() {
                [] => "something else".to_string(),
                [one] => (*one).to_string(),
                [init @ .., last] => format!("{} or {last}", init.join(", ")),
            }
        }
        ErrorVariant::CustomError { message } => message.clone(),
    };
    at(Span { file, start, end }, |at| SpecError::Syntax { expected, at })
}

/// `a`, `a or b`, `a, b or c`, sorted and without repeats.
fn join_alternatives(mut words: Vec<String>) -> String {
    words.sort_unstable();
    words.dedup();
    match words.as_slice() {
        [] => "something else".to_string(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// Human words for grammar rules, used in "expected …".
fn describe(rule: Rule) -> &'static str {
    match rule {
        Rule::EOI => "end of file",
        Rule::name => "a name",
        Rule::number | Rule::quantity => "a number",
        Rule::unit => "a unit (m, cm, mm, deg, rad, s, ms)",
        Rule::string | Rule::text => "a quoted string",
        Rule::vector | Rule::pose => "a vector like `(0, 0, 0)`",
        Rule::value => "a value",
        Rule::options | Rule::sim_options => "`{`",
        Rule::noise | Rule::noise_word => "`noise DISTANCE ANGLE`",
        Rule::option => "an option",
        Rule::domain_decl
        | Rule::seed_decl
        | Rule::robot_decl
        | Rule::type_decl
        | Rule::demos_decl
        | Rule::learn_decl
        | Rule::relation_decl
        | Rule::structure_decl
        | Rule::problem_decl
        | Rule::plugins_decl => {
            "a declaration (domain, seed, robot, type, demonstrations, learn, relation, structure, problem, plugins)"
        }
        Rule::urdf
        | Rule::kind
        | Rule::mount
        | Rule::part
        | Rule::grab
        | Rule::group
        | Rule::config
        | Rule::ignore_collision => {
            "a robot setting (urdf, kind, mount, part, grab, group, config, ignore collision)"
        }
        Rule::joint_value => "`joint: value`",
        Rule::mobility | Rule::world_flag => "`movable`, `static`, `marker` or `world`",
        Rule::box_shape | Rule::cylinder_shape | Rule::sphere_shape | Rule::mesh_shape => {
            "a shape (box, cylinder, sphere, mesh)"
        }
        Rule::mesh_mode => "`convex` or `trimesh`",
        Rule::switch => "`on`, `off` or `auto`",
        Rule::at => "`at`",
        Rule::simulate | Rule::files => "a demonstration source (simulate, files)",
        Rule::ros2_map => "`as ros2 {`",
        Rule::ros2_object | Rule::ros2_robot => {
            "a frame mapping (`object TYPE NAME frame \"FRAME\"`, `robot NAME frame \"FRAME\"`)"
        }
        Rule::ros2_held | Rule::ros2_grasp => {
            "how grasps are read (`held topic \"TOPIC\"`, `grasp joint \"JOINT\" below VALUE`)"
        }
        Rule::threshold
        | Rule::position
        | Rule::rotation
        | Rule::components
        | Rule::likelihood
        | Rule::clear
        | Rule::nowhere
        | Rule::symmetry
        | Rule::pair_override
        | Rule::ignore_pair => {
            "a learning setting (threshold, position, rotation, components, likelihood, clear, nowhere, symmetry, pair, ignore pair)"
        }
        Rule::placement => "a placement `TYPE NAME at POSE`",
        Rule::scene_inline | Rule::scene_ref | Rule::goal => "`scene` or `goal`",
        Rule::robot_placement => "`robot NAME`",
        Rule::at_goal | Rule::structure_goal | Rule::atom => {
            "a goal (`relation(a, b)`, `at OBJECT POSE within …`, `structure NAME at ANCHOR`)"
        }
        Rule::plugin | Rule::plugin_kind => "a plugin (planner, refiner, motion)",
        Rule::spec
        | Rule::scene_file
        | Rule::item
        | Rule::robot_item
        | Rule::type_item
        | Rule::demo_source
        | Rule::ros2_item
        | Rule::learn_item
        | Rule::problem_item
        | Rule::scene_item
        | Rule::goal_item
        | Rule::byte_order_mark
        | Rule::WHITESPACE
        | Rule::COMMENT => "more input",
    }
}

struct Lower {
    file: FileId,
}

impl Lower {
    fn span(&self, pair: &Pair<'_, Rule>) -> Span {
        let span = pair.as_span();
        Span { file: self.file, start: span.start(), end: span.end() }
    }

    /// The span of the first `len` bytes of a pair: its keyword.
    fn keyword_span(&self, pair: &Pair<'_, Rule>, keyword: &str) -> Span {
        let start = pair.as_span().start();
        Span { file: self.file, start, end: start + keyword.len() }
    }

    fn name(&self, pair: Pair<'_, Rule>) -> Name {
        Name { text: pair.as_str().to_string(), span: self.span(&pair) }
    }

    fn text(&self, pair: Pair<'_, Rule>) -> Text {
        let span = self.span(&pair);
        let inner = pair.into_inner().next().map_or("", |text| text.as_str());
        Text { text: inner.to_string(), span }
    }

    fn number(&self, pair: &Pair<'_, Rule>) -> f64 {
        // The grammar only admits well-formed decimal numbers; huge ones become infinite and
        // are caught by range checks.
        pair.as_str().parse().unwrap_or(f64::NAN)
    }

    fn unit(&self, pair: Pair<'_, Rule>) -> (Unit, Span) {
        let unit = match pair.as_str() {
            "m" => Unit::Metre,
            "cm" => Unit::Centimetre,
            "mm" => Unit::Millimetre,
            "deg" => Unit::Degree,
            "rad" => Unit::Radian,
            "s" => Unit::Second,
            "Hz" => Unit::Hertz,
            _ => Unit::Millisecond,
        };
        (unit, self.span(&pair))
    }

    fn quantity(&self, pair: Pair<'_, Rule>) -> Quantity {
        let mut inner = pair.into_inner();
        let number = inner.next().expect("a quantity starts with a number");
        let value = self.number(&number);
        let mut span = self.span(&number);
        let unit = inner.next().map(|unit| self.unit(unit));
        // pest includes the whitespace skipped while looking for a unit; end at the last token.
        if let Some((_, unit_span)) = unit {
            span.end = unit_span.end;
        }
        Quantity { value, unit, span }
    }

    fn vector(&self, pair: Pair<'_, Rule>) -> Vector {
        let mut span = self.span(&pair);
        // End at the closing parenthesis or the unit, not at whitespace pest skipped after it.
        span.end = span.start + pair.as_str().rfind(')').map_or(0, |index| index + 1);
        let mut values = [0.0; 3];
        let mut number_spans = [span; 3];
        let mut unit = None;
        let mut index = 0;
        for part in pair.into_inner() {
            if part.as_rule() == Rule::number {
                values[index] = self.number(&part);
                number_spans[index] = self.span(&part);
                index += 1;
            } else {
                unit = Some(self.unit(part));
            }
        }
        if let Some((_, unit_span)) = unit {
            span.end = unit_span.end;
        }
        Vector { values, number_spans, unit, span }
    }

    fn pose(&self, pair: Pair<'_, Rule>) -> Pose {
        let mut span = self.span(&pair);
        let mut inner = pair.into_inner();
        let position = self.vector(inner.next().expect("a pose starts with a vector"));
        let rotation = inner.next().map(|v| self.vector(v));
        span.end = rotation.as_ref().unwrap_or(&position).span.end;
        Pose { position, rotation, span }
    }

    fn at(&self, pair: Option<Pair<'_, Rule>>) -> Option<Pose> {
        pair.map(|at| self.pose(at.into_inner().next().expect("`at` holds a pose")))
    }

    fn value(&self, pair: Pair<'_, Rule>) -> Value {
        let inner = pair.into_inner().next().expect("a value has one alternative");
        match inner.as_rule() {
            Rule::string => Value::Text(self.text(inner)),
            Rule::quantity => Value::Quantity(self.quantity(inner)),
            _ => Value::Word(self.name(inner)),
        }
    }

    fn options(&self, pair: Option<Pair<'_, Rule>>) -> Vec<OptionEntry> {
        let Some(pair) = pair else { return Vec::new() };
        pair.into_inner()
            .map(|option| {
                let mut inner = option.into_inner();
                let key = self.name(inner.next().expect("an option has a key"));
                let value = self.value(inner.next().expect("an option has a value"));
                OptionEntry { key, value }
            })
            .collect()
    }

    /// A `simulate` block's options, with its `noise D A` entries apart.
    fn simulate_options(
        &self,
        pair: Option<Pair<'_, Rule>>,
    ) -> (Vec<OptionEntry>, Vec<NoiseEntry>) {
        let (mut options, mut noise) = (Vec::new(), Vec::new());
        let Some(pair) = pair else { return (options, noise) };
        for entry in pair.into_inner() {
            let rule = entry.as_rule();
            let mut inner = entry.into_inner();
            if rule == Rule::noise {
                let keyword = self.name(inner.next().expect("noise starts with its keyword"));
                let distance = self.quantity(inner.next().expect("noise has a distance"));
                let angle = self.quantity(inner.next().expect("noise has an angle"));
                noise.push(NoiseEntry { keyword, distance, angle });
            } else {
                let key = self.name(inner.next().expect("an option has a key"));
                let value = self.value(inner.next().expect("an option has a value"));
                options.push(OptionEntry { key, value });
            }
        }
        (options, noise)
    }

    fn item(&self, pair: Pair<'_, Rule>) -> Item {
        let rule = pair.as_rule();
        let keyword = pair.as_str().split_whitespace().next().unwrap_or("").to_string();
        let span = self.keyword_span(&pair, &keyword);
        let mut inner = pair.into_inner();
        match rule {
            Rule::domain_decl => Item::Domain(self.name(inner.next().expect("domain name"))),
            Rule::seed_decl => {
                Item::Seed { value: self.quantity(inner.next().expect("seed value")), span }
            }
            Rule::robot_decl => {
                let name = self.name(inner.next().expect("robot name"));
                let items = inner.map(|item| self.robot_item(item)).collect();
                Item::Robot(Robot { name, items })
            }
            Rule::type_decl => {
                let name = self.name(inner.next().expect("type name"));
                let items = inner.map(|item| self.type_item(item)).collect();
                Item::Type(TypeDecl { name, items })
            }
            Rule::demos_decl => Item::Demonstrations {
                sources: inner.map(|source| self.demo_source(source)).collect(),
            },
            Rule::learn_decl => {
                Item::Learn { items: inner.map(|item| self.learn_item(item)).collect(), span }
            }
            Rule::relation_decl => {
                let mut names = Vec::new();
                let mut example = None;
                for part in inner {
                    match part.as_rule() {
                        Rule::name => names.push(self.name(part)),
                        _ => example = Some(self.pose(part)),
                    }
                }
                let [name, first, second, secondary, primary]: [Name; 5] =
                    names.try_into().expect("the relation rule has five names");
                Item::Relation(Relation {
                    name,
                    parameters: [first, second],
                    secondary,
                    primary,
                    example: example.expect("the relation rule ends with a pose"),
                })
            }
            Rule::structure_decl => {
                let name = self.name(inner.next().expect("structure name"));
                let placements = inner.map(|p| self.placement(p)).collect();
                Item::Structure(Structure { name, placements })
            }
            Rule::problem_decl => {
                let name = self.name(inner.next().expect("problem name"));
                let items = inner.map(|item| self.problem_item(item)).collect();
                Item::Problem(Problem { name, items })
            }
            _ => Item::Plugins { plugins: inner.map(|p| self.plugin(p)).collect() },
        }
    }

    fn robot_item(&self, pair: Pair<'_, Rule>) -> (RobotItem, Span) {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let mut next = || inner.next().expect("the grammar guarantees this part");
        let item = match rule {
            Rule::urdf => RobotItem::Urdf(self.text(next())),
            Rule::kind => RobotItem::Kind(self.name(next())),
            Rule::mount => RobotItem::Mount(self.pose(next())),
            Rule::part => RobotItem::Part { name: self.name(next()), link: self.text(next()) },
            Rule::grab => {
                RobotItem::Grab { min: self.quantity(next()), max: self.quantity(next()) }
            }
            Rule::group => {
                let name = self.name(next());
                RobotItem::Group { name, joints: inner.map(|joint| self.text(joint)).collect() }
            }
            Rule::config => {
                let name = self.name(next());
                let values = inner
                    .map(|entry| {
                        let mut parts = entry.into_inner();
                        let joint = parts.next().expect("a joint value names a joint");
                        let joint = match joint.as_rule() {
                            Rule::string => {
                                let text = self.text(joint);
                                Name { text: text.text, span: text.span }
                            }
                            _ => self.name(joint),
                        };
                        (joint, self.quantity(parts.next().expect("a joint value has a value")))
                    })
                    .collect();
                RobotItem::Config { name, values }
            }
            _ => RobotItem::IgnoreCollision(self.text(next()), self.text(next())),
        };
        (item, span)
    }

    fn type_item(&self, pair: Pair<'_, Rule>) -> (TypeItem, Span) {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let written = pair.as_str().to_string();
        let mut inner = pair.into_inner().peekable();
        let item = match rule {
            Rule::mobility => TypeItem::Mobility(Name { text: written, span }),
            Rule::world_flag => TypeItem::World,
            Rule::box_shape => {
                let size = self.vector(inner.next().expect("box size"));
                TypeItem::Box { size, at: self.at(inner.next()) }
            }
            Rule::cylinder_shape => {
                let radius = self.quantity(inner.next().expect("cylinder radius"));
                let height = self.quantity(inner.next().expect("cylinder height"));
                TypeItem::Cylinder { radius, height, at: self.at(inner.next()) }
            }
            Rule::sphere_shape => {
                let radius = self.quantity(inner.next().expect("sphere radius"));
                TypeItem::Sphere { radius, at: self.at(inner.next()) }
            }
            _ => {
                let path = self.text(inner.next().expect("mesh path"));
                let mode = inner.next_if(|p| p.as_rule() == Rule::mesh_mode).map(|p| self.name(p));
                TypeItem::Mesh { path, mode, at: self.at(inner.next()) }
            }
        };
        (item, span)
    }

    fn demo_source(&self, pair: Pair<'_, Rule>) -> DemoSource {
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        match rule {
            Rule::simulate => {
                let demonstrator = self.name(inner.next().expect("demonstrator name"));
                let (options, noise) = self.simulate_options(inner.next());
                DemoSource::Simulate { demonstrator, options, noise }
            }
            _ => {
                let pattern = self.text(inner.next().expect("file pattern"));
                let Some(mapping) = inner.next() else { return DemoSource::Files(pattern) };
                let (mut objects, mut robots) = (Vec::new(), Vec::new());
                for item in mapping.into_inner() {
                    let rule = item.as_rule();
                    let mut parts = item.into_inner();
                    let mut next = || parts.next();
                    if rule == Rule::ros2_object {
                        let type_name = self.name(next().expect("object type"));
                        let name = self.name(next().expect("object name"));
                        let frame = next().map(|frame| self.text(frame));
                        objects.push(Ros2Object { type_name, name, frame });
                    } else {
                        let robot = self.name(next().expect("robot name"));
                        let frame = self.text(next().expect("robot frame"));
                        let (mut held_topic, mut grasp_joint) = (None, None);
                        if let Some(grasp) = next() {
                            let span = self.span(&grasp);
                            let held = grasp.as_rule() == Rule::ros2_held;
                            let mut parts = grasp.into_inner();
                            let text = self.text(parts.next().expect("topic or joint"));
                            match parts.next() {
                                Some(value) if !held => {
                                    grasp_joint = Some((text, self.quantity(value), span));
                                }
                                _ => held_topic = Some(text),
                            }
                        }
                        robots.push(Ros2Robot { robot, frame, held_topic, grasp_joint });
                    }
                }
                DemoSource::Ros2 { pattern, objects, robots }
            }
        }
    }

    fn learn_item(&self, pair: Pair<'_, Rule>) -> LearnItem {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let mut next = || inner.next().expect("the grammar guarantees this part");
        match rule {
            Rule::threshold => LearnItem::Threshold(self.quantity(next()), span),
            Rule::position => {
                let bins = self.vector(next());
                LearnItem::Position { bins, range: inner.next().map(|r| self.vector(r)), span }
            }
            Rule::rotation => LearnItem::Rotation(self.quantity(next()), span),
            Rule::components => LearnItem::Components(self.quantity(next()), span),
            Rule::likelihood => LearnItem::Likelihood(self.quantity(next()), span),
            Rule::clear => LearnItem::Clear(switch(next().as_str()), span),
            Rule::nowhere => LearnItem::Nowhere(switch(next().as_str()), span),
            Rule::symmetry => LearnItem::Symmetry(switch(next().as_str()), span),
            Rule::pair_override => {
                let first = self.name(next());
                let second = self.name(next());
                let items = inner.map(|item| self.learn_item(item)).collect();
                LearnItem::Pair { first, second, items, span }
            }
            _ => LearnItem::IgnorePair(self.name(next()), self.name(next())),
        }
    }

    fn placement(&self, pair: Pair<'_, Rule>) -> Placement {
        let mut inner = pair.into_inner();
        let type_name = self.name(inner.next().expect("placement type"));
        let object = self.name(inner.next().expect("placement object"));
        let pose = self.pose(inner.next().expect("placement pose"));
        Placement { type_name, object, pose }
    }

    fn problem_item(&self, pair: Pair<'_, Rule>) -> ProblemItem {
        let rule = pair.as_rule();
        let keyword = if rule == Rule::goal { "goal" } else { "scene" };
        let span = self.keyword_span(&pair, keyword);
        let mut inner = pair.into_inner();
        match rule {
            Rule::scene_inline => {
                ProblemItem::Scene { items: inner.map(|p| self.scene_item(p)).collect(), span }
            }
            Rule::scene_ref => ProblemItem::SceneFile(self.text(inner.next().expect("scene path"))),
            _ => ProblemItem::Goal { items: inner.map(|p| self.goal_item(p)).collect(), span },
        }
    }

    fn scene_item(&self, pair: Pair<'_, Rule>) -> SceneItem {
        match pair.as_rule() {
            Rule::robot_placement => {
                let mut name = None;
                let mut at = None;
                let mut config = None;
                for part in pair.into_inner() {
                    match part.as_rule() {
                        Rule::pose => at = Some(self.pose(part)),
                        _ if name.is_none() => name = Some(self.name(part)),
                        _ => config = Some(self.name(part)),
                    }
                }
                SceneItem::Robot {
                    name: name.expect("a robot placement names the robot"),
                    at,
                    config,
                }
            }
            _ => SceneItem::Object(self.placement(pair)),
        }
    }

    fn goal_item(&self, pair: Pair<'_, Rule>) -> GoalItem {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        match rule {
            Rule::at_goal => {
                let object = self.name(inner.next().expect("at-goal object"));
                let pose = self.pose(inner.next().expect("at-goal pose"));
                let distance = self.quantity(inner.next().expect("at-goal distance"));
                let angle = self.quantity(inner.next().expect("at-goal angle"));
                GoalItem::At { object, pose, distance, angle }
            }
            Rule::structure_goal => {
                let name = self.name(inner.next().expect("structure name"));
                let anchor = self.name(inner.next().expect("structure anchor"));
                GoalItem::Structure {
                    name,
                    anchor,
                    offset: inner.next().map(|p| self.pose(p)),
                    span,
                }
            }
            _ => {
                let relation = self.name(inner.next().expect("atom relation"));
                GoalItem::Atom { relation, arguments: inner.map(|a| self.name(a)).collect(), span }
            }
        }
    }

    fn plugin(&self, pair: Pair<'_, Rule>) -> Plugin {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        let kind = self.name(inner.next().expect("plugin kind"));
        let source = inner.next().expect("plugin source");
        let source = match source.as_rule() {
            Rule::string => PluginRef::Library(self.text(source)),
            _ => PluginRef::Builtin(self.name(source)),
        };
        Plugin { kind, source, options: self.options(inner.next()), span }
    }
}

/// The value of a `switch` (the grammar allows only these three words).
fn switch(word: &str) -> lamp_spec::Switch {
    match word {
        "on" => lamp_spec::Switch::On,
        "off" => lamp_spec::Switch::Off,
        _ => lamp_spec::Switch::Auto,
    }
}
