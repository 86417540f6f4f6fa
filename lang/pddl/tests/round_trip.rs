//! The writer's output parses back to the same model, is a fixed point, and is accepted by Fast
//! Downward's translator (the reference PDDL front end).

use lamp_pddl::{
    Action, Atom, Condition, Domain, Literal, Predicate, Problem, Term, TypeDecl, Typed,
    parse_domain, parse_problem, write_domain, write_problem,
};

fn var(name: &str) -> Term {
    Term::Variable(name.to_owned())
}

fn predicate(name: &str, parameters: &[(&str, &str)]) -> Predicate {
    Predicate {
        name: name.to_owned(),
        parameters: parameters.iter().map(|(n, t)| Typed::new(*n, *t)).collect(),
        span: lamp_pddl::Span::default(),
    }
}

/// A domain that uses every feature of the subset: a type hierarchy, a constant, equality,
/// negative preconditions, adds and deletes.
pub fn sample_domain() -> Domain {
    let mut domain = Domain::new("warehouse");
    domain.types = vec![
        TypeDecl { name: "item".into(), parent: "object".into(), span: Default::default() },
        TypeDecl { name: "can".into(), parent: "item".into(), span: Default::default() },
        TypeDecl { name: "place".into(), parent: "object".into(), span: Default::default() },
    ];
    domain.constants = vec![Typed::new("dock", "place")];
    domain.predicates = vec![
        predicate("at", &[("i", "item"), ("p", "place")]),
        predicate("holding", &[("i", "item")]),
        predicate("broken", &[("i", "item")]),
        predicate("hand-empty", &[]),
    ];
    let mut pick = Action::new("pick", vec![Typed::new("i", "item"), Typed::new("p", "place")]);
    pick.precondition = vec![
        Condition::atom(Atom::new("at", vec![var("i"), var("p")])),
        Condition::atom(Atom::new("hand-empty", vec![])),
        Condition::not_atom(Atom::new("broken", vec![var("i")])),
    ];
    pick.add = vec![Atom::new("holding", vec![var("i")])];
    pick.delete = vec![Atom::new("at", vec![var("i"), var("p")]), Atom::new("hand-empty", vec![])];
    let mut stack =
        Action::new("drop-at-dock", vec![Typed::new("a", "can"), Typed::new("b", "can")]);
    stack.precondition = vec![
        Condition::distinct(var("a"), var("b")),
        Condition::atom(Atom::new("holding", vec![var("a")])),
        Condition::atom(Atom::new("at", vec![var("b"), Term::Constant("dock".into())])),
    ];
    stack.add = vec![
        Atom::new("at", vec![var("a"), Term::Constant("dock".into())]),
        Atom::new("hand-empty", vec![]),
    ];
    stack.delete = vec![Atom::new("holding", vec![var("a")])];
    let noop = Action::new("wait", vec![]);
    domain.actions = vec![pick, stack, noop];
    domain
}

pub fn sample_problem() -> Problem {
    let mut problem = Problem::new("move-two", "warehouse");
    problem.objects =
        vec![Typed::new("c1", "can"), Typed::new("c2", "can"), Typed::new("shelf", "place")];
    problem.init = vec![
        Atom::ground("at", &["c1", "shelf"]),
        Atom::ground("at", &["c2", "dock"]),
        Atom::ground("hand-empty", &[]),
    ];
    problem.goal = vec![
        Literal::positive(Atom::ground("at", &["c1", "dock"])),
        Literal::negative(Atom::ground("broken", &["c1"])),
    ];
    problem
}

#[test]
fn written_domain_and_problem_parse_back_identically() {
    let domain = sample_domain();
    let text = write_domain(&domain);
    let parsed = parse_domain(&text).unwrap_or_else(|e| panic!("{e:#?}\n{text}"));
    let mut expected = domain.clone();
    expected.requirements = domain.used_requirements();
    assert_eq!(parsed, expected);
    assert_eq!(write_domain(&parsed), text);
    assert_eq!(parsed.to_string(), text, "Display is the writer");

    let problem = sample_problem();
    let problem_text = write_problem(&problem);
    let parsed_problem =
        parse_problem(&problem_text, &parsed).unwrap_or_else(|e| panic!("{e:#?}\n{problem_text}"));
    assert_eq!(parsed_problem, problem);
    assert_eq!(write_problem(&parsed_problem), problem_text);
}

#[test]
fn written_layout_is_stable() {
    insta::assert_snapshot!("domain", write_domain(&sample_domain()));
    insta::assert_snapshot!("problem", write_problem(&sample_problem()));
}

#[test]
fn names_that_would_not_read_back_are_rejected() {
    let mut domain = sample_domain();
    domain.predicates[0].name = "At".into();
    domain.actions[0].parameters[0].name = "1st".into();
    let errors = lamp_pddl::check_domain(&domain);
    let names: Vec<_> = errors
        .iter()
        .filter_map(|error| match error {
            lamp_pddl::PddlError::InvalidName { name, .. } => Some(name.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(names, ["1st", "At"]);
}

#[test]
fn canonical_sort_orders_by_documented_keys() {
    let mut domain = sample_domain();
    domain.sort_canonical();
    let names: Vec<_> = domain.actions.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["drop-at-dock", "pick", "wait"]);
    let pick = domain.action("pick").expect("pick exists");
    assert!(
        matches!(&pick.precondition[0], Condition::Atom { atom, positive: true } if atom.predicate == "at")
    );
    assert!(matches!(&pick.precondition[2], Condition::Atom { positive: false, .. }));
    let drop = domain.action("drop-at-dock").expect("exists");
    assert!(matches!(drop.precondition[0], Condition::Equality { .. }));
    let predicates: Vec<_> = domain.predicates.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(predicates, ["at", "broken", "hand-empty", "holding"]);
}

/// Runs Fast Downward's translator on the written files; it must translate without error.
#[test]
fn fast_downward_translator_accepts_written_pddl() {
    let require = std::env::var("LAMP_REQUIRE_ORACLES").is_ok_and(|v| v == "1");
    let available = std::process::Command::new("python3")
        .args(["-c", "import fast_downward.translate"])
        .output()
        .is_ok_and(|output| output.status.success());
    if !available {
        assert!(!require, "Fast Downward's translator (pip fast-downward-translate) is required");
        println!("skipped: python3 -m fast_downward.translate is not installed");
        return;
    }
    let directory = tempfile::tempdir().expect("a scratch directory");
    let mut cases =
        vec![("sample", write_domain(&sample_domain()), write_problem(&sample_problem()))];
    for name in ["packing", "cafeworld", "jenga"] {
        let path = format!("{}/tests/fixtures/paper_{name}.pddl", env!("CARGO_MANIFEST_DIR"));
        let domain = parse_domain(&std::fs::read_to_string(path).expect("fixture")).expect("valid");
        // A one-object-per-type problem with an empty init and goal is enough to exercise the
        // translator's parser and normaliser on the written domain.
        let mut problem = Problem::new("smoke", domain.name.clone());
        problem.objects = domain
            .types
            .iter()
            .map(|t| Typed::new(format!("{}1", t.name), t.name.clone()))
            .collect();
        cases.push((name, write_domain(&domain), write_problem(&problem)));
    }
    for (name, domain_text, problem_text) in cases {
        let domain_path = directory.path().join(format!("{name}-domain.pddl"));
        let problem_path = directory.path().join(format!("{name}-problem.pddl"));
        std::fs::write(&domain_path, &domain_text).expect("write domain");
        std::fs::write(&problem_path, &problem_text).expect("write problem");
        let output = std::process::Command::new("python3")
            .args(["-m", "fast_downward.translate"])
            .arg(&domain_path)
            .arg(&problem_path)
            .arg("--sas-file")
            .arg(directory.path().join(format!("{name}.sas")))
            .output()
            .expect("python3 runs");
        assert!(
            output.status.success(),
            "{name}: translator failed\n{}\n{}\n{domain_text}\n{problem_text}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        let sas =
            std::fs::read_to_string(directory.path().join(format!("{name}.sas"))).expect("sas");
        assert!(sas.starts_with("begin_version"), "{name}: not a SAS file");
    }
}
