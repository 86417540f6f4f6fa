//! The PDDL data model: domains, problems, actions and atoms, as plain values.
//!
//! Names are stored in lower case (PDDL names are case-insensitive); variables are stored without
//! their leading `?`. Every list keeps the order in which it was written or built: the writer emits
//! that order unchanged, and [`Domain::sort_canonical`] / [`Problem::sort_canonical`] sort it by the
//! documented keys when a caller wants a canonical form.
//!
//! Spans locate a node in the source it was parsed from. They are metadata: two models that differ
//! only in spans compare equal, so a model built in memory equals the same model parsed back.

use std::cmp::Ordering;

/// The root of every type hierarchy; declared implicitly.
pub const OBJECT_TYPE: &str = "object";

/// A byte range in the source text a node was parsed from.
///
/// Spans never take part in equality (see the module documentation).
#[derive(Clone, Copy, Debug, Default)]
pub struct Span {
    /// Byte offset of the first character.
    pub start: usize,
    /// Byte offset one past the last character.
    pub end: usize,
}

impl Span {
    /// A span from `start` (inclusive) to `end` (exclusive).
    #[must_use]
    pub fn new(start: usize, end: usize) -> Self {
        Self { start, end }
    }

    /// The length in bytes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.end.saturating_sub(self.start)
    }

    /// Whether the span covers no byte.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl PartialEq for Span {
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

impl Eq for Span {}

impl From<Span> for miette::SourceSpan {
    fn from(span: Span) -> Self {
        (span.start, span.len()).into()
    }
}

/// A PDDL requirement flag that lamp understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Requirement {
    /// `:strips`: add and delete effects, conjunctive preconditions.
    Strips,
    /// `:typing`: a type hierarchy rooted at `object`.
    Typing,
    /// `:equality`: `(= ?a ?b)` in preconditions.
    Equality,
    /// `:negative-preconditions`: `(not (p ...))` in preconditions and goals.
    NegativePreconditions,
}

impl Requirement {
    /// The flag as written in PDDL, with its leading colon.
    #[must_use]
    pub fn keyword(self) -> &'static str {
        match self {
            Self::Strips => ":strips",
            Self::Typing => ":typing",
            Self::Equality => ":equality",
            Self::NegativePreconditions => ":negative-preconditions",
        }
    }

    /// The requirement named by `keyword` (lower case, with its colon), if lamp supports it.
    #[must_use]
    pub fn from_keyword(keyword: &str) -> Option<Self> {
        match keyword {
            ":strips" => Some(Self::Strips),
            ":typing" => Some(Self::Typing),
            ":equality" => Some(Self::Equality),
            ":negative-preconditions" => Some(Self::NegativePreconditions),
            _ => None,
        }
    }
}

/// A declared type and its parent (`object` when none was written).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TypeDecl {
    pub name: String,
    pub parent: String,
    pub span: Span,
}

/// A name with a type: a constant, an object, a parameter or a predicate argument.
///
/// For parameters and predicate arguments the name is a variable name without its `?`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Typed {
    pub name: String,
    pub type_name: String,
    pub span: Span,
}

impl Typed {
    /// A typed name with no source location.
    #[must_use]
    pub fn new(name: impl Into<String>, type_name: impl Into<String>) -> Self {
        Self { name: name.into(), type_name: type_name.into(), span: Span::default() }
    }
}

/// A predicate declaration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Predicate {
    pub name: String,
    pub parameters: Vec<Typed>,
    pub span: Span,
}

/// An argument of an atom: a variable (a parameter of the enclosing action) or a constant/object.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Term {
    /// A variable, stored without its `?`.
    Variable(String),
    /// A domain constant or a problem object.
    Constant(String),
}

impl Term {
    /// The name without any `?`.
    #[must_use]
    pub fn name(&self) -> &str {
        match self {
            Self::Variable(name) | Self::Constant(name) => name,
        }
    }
}

/// A predicate applied to arguments.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Atom {
    pub predicate: String,
    pub arguments: Vec<Term>,
    pub span: Span,
}

impl Atom {
    /// An atom with no source location.
    #[must_use]
    pub fn new(predicate: impl Into<String>, arguments: Vec<Term>) -> Self {
        Self { predicate: predicate.into(), arguments, span: Span::default() }
    }

    /// A ground atom over constants/objects.
    #[must_use]
    pub fn ground(predicate: impl Into<String>, objects: &[&str]) -> Self {
        Self::new(
            predicate,
            objects.iter().map(|name| Term::Constant((*name).to_owned())).collect(),
        )
    }

    /// The canonical sort key: predicate name, then arguments in order (variables before constants).
    #[must_use]
    pub fn sort_key(&self) -> (&str, &[Term]) {
        (&self.predicate, &self.arguments)
    }

    fn canonical_order(&self, other: &Self) -> Ordering {
        self.sort_key().cmp(&other.sort_key())
    }
}

/// One conjunct of a precondition.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Condition {
    /// `(p ...)` when `positive`, `(not (p ...))` otherwise.
    Atom { atom: Atom, positive: bool },
    /// `(= a b)` when `positive`, `(not (= a b))` otherwise.
    Equality { left: Term, right: Term, positive: bool, span: Span },
}

impl Condition {
    /// A positive atom condition.
    #[must_use]
    pub fn atom(atom: Atom) -> Self {
        Self::Atom { atom, positive: true }
    }

    /// A negated atom condition.
    #[must_use]
    pub fn not_atom(atom: Atom) -> Self {
        Self::Atom { atom, positive: false }
    }

    /// `(not (= left right))`.
    #[must_use]
    pub fn distinct(left: Term, right: Term) -> Self {
        Self::Equality { left, right, positive: false, span: Span::default() }
    }

    /// Canonical order: inequalities and equalities first, then positive atoms, then negative
    /// atoms; within a group by atom sort key (or by the pair of terms).
    fn canonical_order(&self, other: &Self) -> Ordering {
        fn group(condition: &Condition) -> u8 {
            match condition {
                Condition::Equality { .. } => 0,
                Condition::Atom { positive: true, .. } => 1,
                Condition::Atom { positive: false, .. } => 2,
            }
        }
        group(self).cmp(&group(other)).then_with(|| match (self, other) {
            (Self::Atom { atom: left, .. }, Self::Atom { atom: right, .. }) => {
                left.canonical_order(right)
            }
            (
                Self::Equality { left: a, right: b, positive: p, .. },
                Self::Equality { left: c, right: d, positive: q, .. },
            ) => (p, a, b).cmp(&(q, c, d)),
            _ => Ordering::Equal,
        })
    }
}

/// A goal conjunct: a ground atom that must hold (`positive`) or must not hold.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Literal {
    pub atom: Atom,
    pub positive: bool,
}

impl Literal {
    /// A positive literal.
    #[must_use]
    pub fn positive(atom: Atom) -> Self {
        Self { atom, positive: true }
    }

    /// A negative literal.
    #[must_use]
    pub fn negative(atom: Atom) -> Self {
        Self { atom, positive: false }
    }
}

/// A STRIPS action schema.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Action {
    pub name: String,
    pub parameters: Vec<Typed>,
    /// A conjunction; empty means "always applicable".
    pub precondition: Vec<Condition>,
    /// Atoms made true.
    pub add: Vec<Atom>,
    /// Atoms made false (applied before the adds, as PDDL prescribes).
    pub delete: Vec<Atom>,
    pub span: Span,
}

impl Action {
    /// An action with no source location.
    #[must_use]
    pub fn new(name: impl Into<String>, parameters: Vec<Typed>) -> Self {
        Self {
            name: name.into(),
            parameters,
            precondition: Vec::new(),
            add: Vec::new(),
            delete: Vec::new(),
            span: Span::default(),
        }
    }
}

/// A PDDL domain.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Domain {
    pub name: String,
    /// Requirements as declared in the source. The writer ignores this field and declares only the
    /// requirements the model actually uses (see [`Domain::used_requirements`]).
    pub requirements: Vec<Requirement>,
    /// Declared types, excluding the implicit `object`.
    pub types: Vec<TypeDecl>,
    pub constants: Vec<Typed>,
    pub predicates: Vec<Predicate>,
    pub actions: Vec<Action>,
    pub span: Span,
}

impl Domain {
    /// An empty domain.
    #[must_use]
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Self::default() }
    }

    /// The requirements this domain needs, in canonical order: `:strips` always; `:typing` when a
    /// type other than `object` is declared or used; `:equality` when an action compares terms;
    /// `:negative-preconditions` when a precondition negates an atom.
    #[must_use]
    pub fn used_requirements(&self) -> Vec<Requirement> {
        let mut used = vec![Requirement::Strips];
        let typed = |typed: &Typed| typed.type_name != OBJECT_TYPE;
        let uses_typing = !self.types.is_empty()
            || self.constants.iter().any(typed)
            || self.predicates.iter().flat_map(|p| &p.parameters).any(typed)
            || self.actions.iter().flat_map(|a| &a.parameters).any(typed);
        if uses_typing {
            used.push(Requirement::Typing);
        }
        let conditions = || self.actions.iter().flat_map(|action| &action.precondition);
        if conditions().any(|c| matches!(c, Condition::Equality { .. })) {
            used.push(Requirement::Equality);
        }
        if conditions().any(|c| matches!(c, Condition::Atom { positive: false, .. })) {
            used.push(Requirement::NegativePreconditions);
        }
        used
    }

    /// The predicate declaration named `name`.
    #[must_use]
    pub fn predicate(&self, name: &str) -> Option<&Predicate> {
        self.predicates.iter().find(|predicate| predicate.name == name)
    }

    /// The action named `name`.
    #[must_use]
    pub fn action(&self, name: &str) -> Option<&Action> {
        self.actions.iter().find(|action| action.name == name)
    }

    /// The parent of `type_name`, or `None` for `object` and undeclared types.
    #[must_use]
    pub fn parent_type(&self, type_name: &str) -> Option<&str> {
        self.types.iter().find(|decl| decl.name == type_name).map(|decl| decl.parent.as_str())
    }

    /// Whether `sub` is `sup` or a descendant of it. Terminates on cyclic hierarchies.
    #[must_use]
    pub fn is_subtype(&self, sub: &str, sup: &str) -> bool {
        let mut current = sub;
        for _ in 0..=self.types.len() + 1 {
            if current == sup || sup == OBJECT_TYPE {
                return true;
            }
            match self.parent_type(current) {
                Some(parent) => current = parent,
                None => return false,
            }
        }
        false
    }

    /// Sorts every list by its canonical key: types, constants and predicates by name; actions by
    /// name; within an action, parameters keep their order (it is the action's signature),
    /// preconditions as in the canonical condition order (equalities, positive atoms, negative
    /// atoms; each by predicate then arguments), adds and deletes by predicate then arguments.
    pub fn sort_canonical(&mut self) {
        self.requirements.sort();
        self.requirements.dedup();
        self.types.sort_by(|a, b| a.name.cmp(&b.name));
        self.constants.sort_by(|a, b| a.name.cmp(&b.name));
        self.predicates.sort_by(|a, b| a.name.cmp(&b.name));
        self.actions.sort_by(|a, b| a.name.cmp(&b.name));
        for action in &mut self.actions {
            action.precondition.sort_by(Condition::canonical_order);
            action.add.sort_by(Atom::canonical_order);
            action.delete.sort_by(Atom::canonical_order);
        }
    }
}

/// A PDDL problem.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Problem {
    pub name: String,
    /// The name of the domain this problem is for.
    pub domain: String,
    pub objects: Vec<Typed>,
    /// Ground atoms true initially; every other atom is false.
    pub init: Vec<Atom>,
    /// A conjunction of ground literals.
    pub goal: Vec<Literal>,
    pub span: Span,
    /// Where the domain name is written.
    pub domain_span: Span,
}

impl Problem {
    /// An empty problem for `domain`.
    #[must_use]
    pub fn new(name: impl Into<String>, domain: impl Into<String>) -> Self {
        Self { name: name.into(), domain: domain.into(), ..Self::default() }
    }

    /// Whether the goal negates an atom (then the problem needs `:negative-preconditions`).
    #[must_use]
    pub fn uses_negative_goals(&self) -> bool {
        self.goal.iter().any(|literal| !literal.positive)
    }

    /// Sorts objects by name, init atoms and goal literals by predicate then arguments (positive
    /// goal literals before negative ones).
    pub fn sort_canonical(&mut self) {
        self.objects.sort_by(|a, b| a.name.cmp(&b.name));
        self.init.sort_by(Atom::canonical_order);
        self.goal.sort_by(|a, b| {
            b.positive.cmp(&a.positive).then_with(|| a.atom.canonical_order(&b.atom))
        });
    }
}
