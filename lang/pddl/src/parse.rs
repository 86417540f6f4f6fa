//! The PDDL reader: pest grammar (`pddl.pest`) to model, then the semantic checks.
//!
//! Keywords and names are case-insensitive in PDDL; the reader lowers every name to ASCII lower case
//! (names are ASCII by the grammar, so spans stay exact). Requirements outside the subset that only
//! relax what may be written (`:adl`, `:conditional-effects`, quantified and disjunctive
//! preconditions) are tolerated when declared, because learned domains routinely declare them without
//! using them; using the construct is an error. Requirements that change the language (numeric
//! fluents, durative actions, ...) are rejected where declared.

use pest::Parser as _;
use pest::iterators::Pair;
use pest_derive::Parser;

use crate::check::{check_domain, check_problem};
use crate::error::{PddlError, PddlErrors};
use crate::model::{
    Action, Atom, Condition, Domain, Literal, OBJECT_TYPE, Predicate, Problem, Requirement, Span,
    Term, TypeDecl, Typed,
};

#[derive(Parser)]
#[grammar = "pddl.pest"]
struct PddlParser;

/// Requirements that may be declared but whose constructs are rejected when used.
const TOLERATED_REQUIREMENTS: &[&str] = &[
    ":adl",
    ":conditional-effects",
    ":disjunctive-preconditions",
    ":existential-preconditions",
    ":quantified-preconditions",
    ":universal-preconditions",
];

/// Parses and checks a domain.
///
/// # Errors
/// Every syntax or semantic problem found, each with a span into `source`.
pub fn parse_domain(source: &str) -> Result<Domain, PddlErrors> {
    let file = parse_rule(Rule::domain_file, source)?;
    let mut lowering = Lowering::default();
    let domain = file
        .into_inner()
        .find(|pair| pair.as_rule() == Rule::domain)
        .map(|pair| lowering.domain(pair))
        .unwrap_or_default();
    let mut errors = lowering.errors;
    if errors.is_empty() {
        errors = check_domain(&domain);
    }
    if errors.is_empty() { Ok(domain) } else { Err(PddlErrors { errors }) }
}

/// Parses a problem and checks it against `domain`.
///
/// # Errors
/// Every syntax or semantic problem found, each with a span into `source`.
pub fn parse_problem(source: &str, domain: &Domain) -> Result<Problem, PddlErrors> {
    let file = parse_rule(Rule::problem_file, source)?;
    let mut lowering = Lowering::default();
    let problem = file
        .into_inner()
        .find(|pair| pair.as_rule() == Rule::problem)
        .map(|pair| lowering.problem(pair))
        .unwrap_or_default();
    let mut errors = lowering.errors;
    if errors.is_empty() {
        errors = check_problem(domain, &problem);
    }
    if errors.is_empty() { Ok(problem) } else { Err(PddlErrors { errors }) }
}

fn parse_rule(rule: Rule, source: &str) -> Result<Pair<'_, Rule>, PddlErrors> {
    match PddlParser::parse(rule, source) {
        Ok(mut pairs) => pairs.next().ok_or_else(|| PddlErrors {
            errors: vec![PddlError::Syntax {
                message: "empty input".to_owned(),
                span: (0, 0).into(),
                label: "expected a PDDL definition".to_owned(),
            }],
        }),
        Err(error) => Err(PddlErrors { errors: vec![syntax_error(error, source)] }),
    }
}

/// How much of the offending token a syntax error quotes.
const MAX_TOKEN_CHARS: usize = 20;

fn syntax_error(error: pest::error::Error<Rule>, source: &str) -> PddlError {
    let (start, end) = match error.location {
        pest::error::InputLocation::Pos(position) => (position, position),
        pest::error::InputLocation::Span((start, end)) => (start, end),
    };
    let found = source.get(start..).and_then(|rest| rest.split_whitespace().next()).map_or_else(
        || "end of input".to_owned(),
        |token| format!("`{}`", token.chars().take(MAX_TOKEN_CHARS).collect::<String>()),
    );
    let label = match &error.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } => {
            let mut expected: Vec<String> = positives.iter().map(rule_description).collect();
            expected.sort();
            expected.dedup();
            match expected.as_slice() {
                [] => "unexpected input".to_owned(),
                [one] => format!("expected {one}"),
                [init @ .., last] => format!("expected {} or {last}", init.join(", ")),
            }
        }
        pest::error::ErrorVariant::CustomError { message } => message.clone(),
    };
    PddlError::Syntax {
        message: format!("unexpected {found}"),
        span: (start, end - start).into(),
        label,
    }
}

fn rule_description(rule: &Rule) -> String {
    match rule {
        Rule::EOI => "end of input",
        Rule::name => "a name",
        Rule::variable => "a variable (`?name`)",
        Rule::requirement => "a requirement (`:name`)",
        Rule::typed_name_group | Rule::untyped_names | Rule::typed_names => "a name",
        Rule::typed_variable_group | Rule::untyped_variables | Rule::typed_variables => {
            "a variable (`?name`)"
        }
        Rule::type_name => "a type name",
        Rule::domain_section | Rule::requirements | Rule::types | Rule::constants => {
            "a domain section"
        }
        Rule::predicates | Rule::action | Rule::unsupported_section => "a domain section",
        Rule::predicate => "a predicate declaration",
        Rule::problem_section | Rule::objects | Rule::init | Rule::goal => "a problem section",
        Rule::precondition | Rule::and_conditions | Rule::negation | Rule::equality => {
            "a condition"
        }
        Rule::atom => "an atom",
        Rule::effect | Rule::and_effects => "an effect",
        Rule::empty => "`()`",
        Rule::unsupported_formula | Rule::unsupported_init => "a formula",
        Rule::keyword_and => "`and`",
        Rule::keyword_not => "`not`",
        _ => return format!("{rule:?}"),
    }
    .to_owned()
}

fn span_of(pair: &Pair<'_, Rule>) -> Span {
    let span = pair.as_span();
    Span::new(span.start(), span.end())
}

fn lower(pair: &Pair<'_, Rule>) -> String {
    pair.as_str().to_ascii_lowercase()
}

/// Turns the pest tree into the model, collecting the errors that only the tree can see
/// (unsupported constructs and requirements).
#[derive(Default)]
struct Lowering {
    errors: Vec<PddlError>,
}

impl Lowering {
    fn unsupported(&mut self, feature: String, span: Span) {
        self.errors.push(PddlError::Unsupported { feature, span: Some(span.into()) });
    }

    fn unsupported_form(&mut self, pair: &Pair<'_, Rule>) {
        let head =
            pair.clone().into_inner().next().map_or_else(|| lower(pair), |keyword| lower(&keyword));
        let feature = match head.as_str() {
            "" => lower(pair),
            _ if pair.as_rule() == Rule::unsupported_init => "numeric fluents".to_owned(),
            _ if pair.as_rule() == Rule::unsupported_either => "either".to_owned(),
            _ => head,
        };
        self.unsupported(feature, span_of(pair));
    }

    fn domain(&mut self, pair: Pair<'_, Rule>) -> Domain {
        let mut domain = Domain { span: span_of(&pair), ..Domain::default() };
        for item in pair.into_inner() {
            match item.as_rule() {
                Rule::name => domain.name = lower(&item),
                Rule::requirements => domain.requirements = self.requirements(item),
                Rule::types => {
                    domain.types = self
                        .typed_names_of(item)
                        .into_iter()
                        .filter(|typed| typed.name != OBJECT_TYPE)
                        .map(|typed| TypeDecl {
                            name: typed.name,
                            parent: typed.type_name,
                            span: typed.span,
                        })
                        .collect();
                }
                Rule::constants => domain.constants = self.typed_names_of(item),
                Rule::predicates => {
                    for predicate in item.into_inner() {
                        let span = span_of(&predicate);
                        let mut inner = predicate.into_inner();
                        let name = inner.next().map(|name| lower(&name)).unwrap_or_default();
                        let parameters =
                            inner.next().map(|p| self.typed_names(p)).unwrap_or_default();
                        domain.predicates.push(Predicate { name, parameters, span });
                    }
                }
                Rule::action => domain.actions.push(self.action(item)),
                Rule::unsupported_section => self.unsupported_form(&item),
                _ => {}
            }
        }
        domain
    }

    fn requirements(&mut self, pair: Pair<'_, Rule>) -> Vec<Requirement> {
        let mut requirements = Vec::new();
        for item in pair.into_inner().filter(|item| item.as_rule() == Rule::requirement) {
            let keyword = lower(&item);
            if let Some(requirement) = Requirement::from_keyword(&keyword) {
                requirements.push(requirement);
            } else if !TOLERATED_REQUIREMENTS.contains(&keyword.as_str()) {
                self.unsupported(keyword, span_of(&item));
            }
        }
        requirements
    }

    /// Lowers the `typed_names` child of a section.
    fn typed_names_of(&mut self, section: Pair<'_, Rule>) -> Vec<Typed> {
        section
            .into_inner()
            .find(|pair| pair.as_rule() == Rule::typed_names)
            .map(|pair| self.typed_names(pair))
            .unwrap_or_default()
    }

    /// Lowers `typed_names` or `typed_variables` (variables lose their `?`).
    fn typed_names(&mut self, pair: Pair<'_, Rule>) -> Vec<Typed> {
        let mut list = Vec::new();
        for group in pair.into_inner() {
            let typed_group =
                matches!(group.as_rule(), Rule::typed_name_group | Rule::typed_variable_group);
            let mut names = Vec::new();
            let mut type_name = OBJECT_TYPE.to_owned();
            for item in group.into_inner() {
                match item.as_rule() {
                    Rule::type_name => {
                        if let Some(inner) = item.into_inner().next() {
                            if inner.as_rule() == Rule::unsupported_either {
                                self.unsupported_form(&inner);
                            } else {
                                type_name = lower(&inner);
                            }
                        }
                    }
                    _ => names
                        .push((lower(&item).trim_start_matches('?').to_owned(), span_of(&item))),
                }
            }
            if !typed_group {
                type_name = OBJECT_TYPE.to_owned();
            }
            list.extend(names.into_iter().map(|(name, span)| Typed {
                name,
                type_name: type_name.clone(),
                span,
            }));
        }
        list
    }

    fn action(&mut self, pair: Pair<'_, Rule>) -> Action {
        let mut action = Action { span: span_of(&pair), ..Action::new("", Vec::new()) };
        for item in pair.into_inner() {
            match item.as_rule() {
                Rule::name => action.name = lower(&item),
                Rule::typed_variables => action.parameters = self.typed_names(item),
                Rule::precondition => action.precondition = self.conditions(item),
                Rule::effect => self.effects(item, &mut action),
                _ => {}
            }
        }
        action
    }

    fn conditions(&mut self, pair: Pair<'_, Rule>) -> Vec<Condition> {
        let mut conditions = Vec::new();
        self.collect_conditions(pair, &mut conditions);
        conditions
    }

    fn collect_conditions(&mut self, pair: Pair<'_, Rule>, out: &mut Vec<Condition>) {
        match pair.as_rule() {
            Rule::precondition | Rule::and_conditions => {
                for item in pair.into_inner() {
                    self.collect_conditions(item, out);
                }
            }
            Rule::atom => out.push(Condition::atom(atom(pair))),
            Rule::equality => out.push(equality(pair, true)),
            Rule::negation => {
                if let Some(inner) = negated(pair) {
                    match inner.as_rule() {
                        Rule::atom => out.push(Condition::not_atom(atom(inner))),
                        Rule::equality => out.push(equality(inner, false)),
                        _ => self.unsupported_form(&inner),
                    }
                }
            }
            Rule::unsupported_formula => self.unsupported_form(&pair),
            _ => {}
        }
    }

    fn effects(&mut self, pair: Pair<'_, Rule>, action: &mut Action) {
        match pair.as_rule() {
            Rule::effect | Rule::and_effects => {
                for item in pair.into_inner() {
                    self.effects(item, action);
                }
            }
            Rule::atom => action.add.push(atom(pair)),
            Rule::negation => {
                if let Some(inner) = negated(pair) {
                    match inner.as_rule() {
                        Rule::atom => action.delete.push(atom(inner)),
                        Rule::equality => {
                            self.unsupported("equality in an effect".to_owned(), span_of(&inner))
                        }
                        _ => self.unsupported_form(&inner),
                    }
                }
            }
            Rule::unsupported_formula => self.unsupported_form(&pair),
            _ => {}
        }
    }

    fn problem(&mut self, pair: Pair<'_, Rule>) -> Problem {
        let mut problem = Problem { span: span_of(&pair), ..Problem::default() };
        let mut names = 0;
        for item in pair.into_inner() {
            match item.as_rule() {
                Rule::name => {
                    if names == 0 {
                        problem.name = lower(&item);
                    } else {
                        problem.domain = lower(&item);
                        problem.domain_span = span_of(&item);
                    }
                    names += 1;
                }
                Rule::requirements => {
                    self.requirements(item);
                }
                Rule::objects => problem.objects = self.typed_names_of(item),
                Rule::init => {
                    for element in item.into_inner() {
                        if element.as_rule() == Rule::atom {
                            problem.init.push(atom(element));
                        } else {
                            self.unsupported_form(&element);
                        }
                    }
                }
                Rule::goal => {
                    let mut conditions = Vec::new();
                    for part in item.into_inner() {
                        self.collect_conditions(part, &mut conditions);
                    }
                    for condition in conditions {
                        match condition {
                            Condition::Atom { atom, positive } => {
                                problem.goal.push(Literal { atom, positive });
                            }
                            Condition::Equality { span, .. } => {
                                self.unsupported("equality in a goal".to_owned(), span);
                            }
                        }
                    }
                }
                Rule::unsupported_section => self.unsupported_form(&item),
                _ => {}
            }
        }
        problem
    }
}

/// The formula under a `(not ...)`.
fn negated(pair: Pair<'_, Rule>) -> Option<Pair<'_, Rule>> {
    pair.into_inner().find(|inner| inner.as_rule() != Rule::keyword_not)
}

fn term(pair: &Pair<'_, Rule>) -> Term {
    let text = lower(pair);
    match text.strip_prefix('?') {
        Some(name) => Term::Variable(name.to_owned()),
        None => Term::Constant(text),
    }
}

fn atom(pair: Pair<'_, Rule>) -> Atom {
    let span = span_of(&pair);
    let mut inner = pair.into_inner();
    let predicate = inner.next().map(|name| lower(&name)).unwrap_or_default();
    Atom { predicate, arguments: inner.map(|argument| term(&argument)).collect(), span }
}

fn equality(pair: Pair<'_, Rule>, positive: bool) -> Condition {
    let span = span_of(&pair);
    let mut terms = pair.into_inner().map(|argument| term(&argument));
    let left = terms.next().unwrap_or(Term::Constant(String::new()));
    let right = terms.next().unwrap_or(Term::Constant(String::new()));
    Condition::Equality { left, right, positive, span }
}
