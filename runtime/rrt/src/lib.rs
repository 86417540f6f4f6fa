//! lamp-rrt: RRT-Connect (Kuffner and LaValle, 2000) with path shortcutting, over any configuration
//! space.
//!
//! Two trees grow from the start and the goal; each iteration extends one tree toward a random
//! sample by at most `step` and then greedily connects the other tree toward the new node. Edges
//! are checked at the space's resolution. The trees swap roles every iteration. Nearest neighbours
//! are found by a linear scan: trees stay in the hundreds to low thousands of nodes, and the
//! space's metric (wrapped angles, rotations) is not one a k-d tree can index. Each node keeps its
//! [`Space::distance_form`], so what a distance derives from a configuration is derived once.
//!
//! Deterministic: the same seed and inputs give the same path. The budget is an iteration count
//! (deterministic) and, optionally, a wall-clock limit (a safety net; hitting it is reported).

use std::time::{Duration, Instant};

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// The most states one straight edge may be cut into at the checking resolution, when a path is
/// densified, recorded or checked. A Café base crossing its 10 m floor at the finest resolution
/// the spec allows (1 mm) is 10,000 states and a joint's half turn at 0.001 rad 3,142; 50,000 is
/// beyond any motion of a bundled robot. More is a robot placed kilometres away or a wrong unit,
/// and recording it would take gigabytes (a state holds every body's pose): it is refused.
pub const MAX_EDGE_STEPS: usize = 50_000;

/// What the planner needs from a configuration space.
pub trait Space {
    /// Draws a configuration into `out` (uniform over the free coordinates).
    fn sample(&self, rng: &mut ChaCha8Rng, out: &mut [f64]);
    /// The distance between two configurations (a metric).
    fn distance(&self, a: &[f64], b: &[f64]) -> f64;

    /// `q` in the form [`nearest`](Self::nearest) reads. The search measures every tree node
    /// against every sample, so a space whose distance derives something costly from each
    /// configuration (a rotation from its rotation vector) derives it here, once per node. The
    /// default form is `q` itself.
    fn distance_form(&self, q: &[f64]) -> Vec<f64> {
        q.to_vec()
    }

    /// The index of the first of `forms` (the [`distance_form`](Self::distance_form)s of
    /// configurations) whose configuration is strictly nearest, by [`distance`](Self::distance)
    /// from it, to the configuration whose form is `form`; 0 when none is nearer than infinity.
    /// Whatever shortcut a space takes, the answer is the one this default scan gives, so that
    /// the search grows the same trees. A space overriding one of the two form methods overrides
    /// both.
    fn nearest(&self, forms: &[Vec<f64>], form: &[f64]) -> usize {
        let mut best = (0, f64::INFINITY);
        for (index, candidate) in forms.iter().enumerate() {
            let d = self.distance(candidate, form);
            if d < best.1 {
                best = (index, d);
            }
        }
        best.0
    }

    /// The configuration a fraction `t` of the way from `a` to `b`.
    fn interpolate(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]);
    /// Whether a configuration is valid (within limits, collision-free).
    fn is_valid(&self, q: &[f64]) -> bool;
    /// How many equal sub-steps the straight edge from `a` to `b` needs to respect the
    /// checking resolution (at least 1).
    fn edge_steps(&self, a: &[f64], b: &[f64]) -> usize;

    /// Whether the search should end now, for example because an oracle behind the space failed
    /// or the run was cancelled; checked once per iteration. A space that never stops need not
    /// override it.
    fn should_stop(&self) -> bool {
        false
    }

    /// Whether every state along the edge (endpoints excluded) is valid; an edge of more than
    /// [`MAX_EDGE_STEPS`] sub-steps is not (it could not be recorded).
    fn edge_is_valid(&self, a: &[f64], b: &[f64]) -> bool {
        let steps = self.edge_steps(a, b);
        if steps > MAX_EDGE_STEPS {
            return false;
        }
        let mut q = a.to_vec();
        edge_check_order(steps).into_iter().all(|i| {
            self.interpolate(a, b, i as f64 / steps as f64, &mut q);
            self.is_valid(&q)
        })
    }
}

/// The inner sub-steps `1..steps` of an edge in the order to check them: the middle first, where
/// collisions are likelier than next to known-valid endpoints.
pub fn edge_check_order(steps: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (1..steps).collect();
    order.sort_by_key(|&i| (i as i64 * 2 - steps as i64).abs());
    order
}

/// Budget and step settings.
#[derive(Clone, Debug, PartialEq)]
pub struct RrtConfig {
    /// The longest edge a single extension adds, in the space's metric.
    pub step: f64,
    /// Iterations before giving up (each grows one tree and tries to connect the other).
    pub max_iterations: usize,
    /// Optional wall-clock limit.
    pub timeout: Option<Duration>,
    /// Shortcutting attempts after a path is found (0 disables).
    pub shortcut_attempts: usize,
}

impl Default for RrtConfig {
    fn default() -> Self {
        RrtConfig { step: 0.3, max_iterations: 5_000, timeout: None, shortcut_attempts: 100 }
    }
}

/// Why no path was returned.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum RrtError {
    #[error("the start configuration is in collision or outside the limits")]
    #[diagnostic(code(lamp::motion::invalid_start))]
    InvalidStart,
    #[error("the goal configuration is in collision or outside the limits")]
    #[diagnostic(code(lamp::motion::invalid_goal))]
    InvalidGoal,
    #[error("no path found in {iterations} iterations ({nodes} nodes)")]
    #[diagnostic(code(lamp::motion::no_path), help("raise the iteration budget or move obstacles"))]
    NoPath { iterations: usize, nodes: usize },
    #[error("no path found within {seconds:.3} s ({iterations} iterations)")]
    #[diagnostic(code(lamp::motion::timeout))]
    Timeout { seconds: f64, iterations: usize },
    #[error("the search was stopped by its space after {iterations} iterations")]
    #[diagnostic(code(lamp::motion::stopped))]
    Stopped { iterations: usize },
}

/// Statistics of a successful run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RrtStats {
    pub iterations: usize,
    pub nodes: usize,
    /// Waypoints before and after shortcutting.
    pub raw_waypoints: usize,
    pub waypoints: usize,
}

struct Tree {
    nodes: Vec<Vec<f64>>,
    /// Each node's [`Space::distance_form`], kept so that nearest-neighbour scans derive it once.
    forms: Vec<Vec<f64>>,
    parents: Vec<usize>,
}

impl Tree {
    fn new(space: &impl Space, root: &[f64]) -> Tree {
        Tree {
            nodes: vec![root.to_vec()],
            forms: vec![space.distance_form(root)],
            parents: vec![usize::MAX],
        }
    }

    fn add(&mut self, q: Vec<f64>, form: Vec<f64>, parent: usize) -> usize {
        self.nodes.push(q);
        self.forms.push(form);
        self.parents.push(parent);
        self.nodes.len() - 1
    }

    /// Root-to-node path.
    fn path_to(&self, mut index: usize) -> Vec<Vec<f64>> {
        let mut path = Vec::new();
        while index != usize::MAX {
            path.push(self.nodes[index].clone());
            index = self.parents[index];
        }
        path.reverse();
        path
    }
}

enum Extension {
    Trapped,
    Advanced(usize),
    Reached(usize),
}

/// Extends `tree` toward `target`, whose distance form is `target_form`.
fn extend(
    space: &impl Space,
    tree: &mut Tree,
    target: &[f64],
    target_form: &[f64],
    step: f64,
) -> Extension {
    let near = space.nearest(&tree.forms, target_form);
    let from = tree.nodes[near].clone();
    let distance = space.distance(&from, target);
    let (new, reached) = if distance <= step {
        (target.to_vec(), true)
    } else {
        let mut q = from.clone();
        space.interpolate(&from, target, step / distance, &mut q);
        (q, false)
    };
    if !space.is_valid(&new) || !space.edge_is_valid(&from, &new) {
        return Extension::Trapped;
    }
    let form = if reached { target_form.to_vec() } else { space.distance_form(&new) };
    let index = tree.add(new, form, near);
    if reached { Extension::Reached(index) } else { Extension::Advanced(index) }
}

/// Plans a path from `start` to `goal`; the result starts at `start` and ends at `goal`, and
/// consecutive waypoints are joined by valid straight edges.
pub fn rrt_connect(
    space: &impl Space,
    start: &[f64],
    goal: &[f64],
    config: &RrtConfig,
    rng: &mut ChaCha8Rng,
) -> Result<(Vec<Vec<f64>>, RrtStats), RrtError> {
    if !space.is_valid(start) {
        return Err(RrtError::InvalidStart);
    }
    if !space.is_valid(goal) {
        return Err(RrtError::InvalidGoal);
    }
    let began = Instant::now();
    if space.edge_is_valid(start, goal) {
        let path = vec![start.to_vec(), goal.to_vec()];
        let stats = RrtStats { iterations: 0, nodes: 2, raw_waypoints: 2, waypoints: 2 };
        return Ok((path, stats));
    }
    let mut trees = [Tree::new(space, start), Tree::new(space, goal)];
    let mut sample = start.to_vec();
    for iteration in 1..=config.max_iterations {
        if let Some(limit) = config.timeout
            && began.elapsed() > limit
        {
            return Err(RrtError::Timeout { seconds: limit.as_secs_f64(), iterations: iteration });
        }
        if space.should_stop() {
            return Err(RrtError::Stopped { iterations: iteration });
        }
        let grow = iteration % 2;
        space.sample(rng, &mut sample);
        let sample_form = space.distance_form(&sample);
        let [first, second] = &mut trees;
        let (growing, other) = if grow == 0 { (first, second) } else { (second, first) };
        let new = match extend(space, growing, &sample, &sample_form, config.step) {
            Extension::Trapped => continue,
            Extension::Advanced(index) | Extension::Reached(index) => index,
        };
        let target = growing.nodes[new].clone();
        let target_form = growing.forms[new].clone();
        let connected = loop {
            match extend(space, other, &target, &target_form, config.step) {
                Extension::Trapped => break None,
                Extension::Advanced(_) => {}
                Extension::Reached(index) => break Some(index),
            }
        };
        if let Some(meeting) = connected {
            let (from_start, from_goal) = if grow == 0 { (new, meeting) } else { (meeting, new) };
            let mut path = trees[0].path_to(from_start);
            let mut tail = trees[1].path_to(from_goal);
            tail.pop(); // the meeting configuration is already the end of `path`
            tail.reverse();
            path.extend(tail);
            let raw = path.len();
            let path = shortcut(space, path, config.shortcut_attempts, rng);
            let stats = RrtStats {
                iterations: iteration,
                nodes: trees[0].nodes.len() + trees[1].nodes.len(),
                raw_waypoints: raw,
                waypoints: path.len(),
            };
            return Ok((path, stats));
        }
    }
    Err(RrtError::NoPath {
        iterations: config.max_iterations,
        nodes: trees[0].nodes.len() + trees[1].nodes.len(),
    })
}

/// Random shortcutting: pick two points on the path (anywhere along its edges) and replace what
/// lies between them by a straight edge when that edge, and the two cut edges, are valid.
pub fn shortcut(
    space: &impl Space,
    mut path: Vec<Vec<f64>>,
    attempts: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<Vec<f64>> {
    for _ in 0..attempts {
        if path.len() < 3 {
            break;
        }
        let edges = path.len() - 1;
        let mut i = rng.random_range(0..edges);
        let mut j = rng.random_range(0..edges);
        if i == j {
            continue;
        }
        if i > j {
            std::mem::swap(&mut i, &mut j);
        }
        let (ti, tj): (f64, f64) = (rng.random(), rng.random());
        let mut a = path[i].clone();
        space.interpolate(&path[i], &path[i + 1], ti, &mut a);
        let mut b = path[j].clone();
        space.interpolate(&path[j], &path[j + 1], tj, &mut b);
        // The new pieces of the old edges are checked too: their sub-steps fall between the
        // states the old edges were checked at.
        // The new edge first: it is the one likely to fail.
        let valid = space.is_valid(&a)
            && space.is_valid(&b)
            && space.edge_is_valid(&a, &b)
            && space.edge_is_valid(&path[i], &a)
            && space.edge_is_valid(&b, &path[j + 1]);
        if valid {
            let mut shorter = path[..=i].to_vec();
            shorter.push(a);
            shorter.push(b);
            shorter.extend_from_slice(&path[j + 1..]);
            shorter.dedup_by(|x, y| space.distance(x, y) < 1e-12);
            path = shorter;
        }
    }
    path
}
