//! lamp-rrt's [`Space`] over the host's oracles for one robot: every sample, distance,
//! interpolation and validity check is a host call, and the first host failure is kept.
//!
//! [`Space`]'s methods cannot fail, so a failure (or a cancellation) is remembered, every later
//! question gets a "nothing valid here" answer without asking the host again, and
//! [`Space::should_stop`] ends the search at its next iteration; the planner then returns the
//! remembered error instead of the search's result.

use std::cell::RefCell;

use lamp_plugin_api::{HostError, HostServices, PluginError};
use lamp_rrt::Space;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The configuration space of `robot` as the host knows it.
pub(crate) struct HostSpace<'a> {
    host: &'a dyn HostServices,
    robot: &'a str,
    /// Every configuration of this robot has this many values (the start's).
    dimension: usize,
    failure: RefCell<Option<PluginError>>,
}

impl<'a> HostSpace<'a> {
    pub(crate) fn new(host: &'a dyn HostServices, robot: &'a str, dimension: usize) -> Self {
        Self { host, robot, dimension, failure: RefCell::new(None) }
    }

    /// The first failure, if any call failed or the run was cancelled.
    pub(crate) fn into_failure(self) -> Option<PluginError> {
        self.failure.into_inner()
    }

    fn failed(&self) -> bool {
        self.failure.borrow().is_some()
    }

    fn remember(&self, error: PluginError) {
        self.failure.borrow_mut().get_or_insert(error);
    }

    /// The host's answer, or `fallback` once anything has failed.
    fn ask<T>(&self, fallback: T, call: impl FnOnce() -> Result<T, HostError>) -> T {
        if self.failed() {
            return fallback;
        }
        call().unwrap_or_else(|error| {
            self.remember(error.into());
            fallback
        })
    }

    /// Copies a configuration the host returned into `out`, checking its length.
    fn write_configuration(
        &self,
        service: &str,
        answer: Result<Vec<f64>, HostError>,
        out: &mut [f64],
    ) {
        match answer {
            Ok(q) if q.len() == out.len() => out.copy_from_slice(&q),
            Ok(q) => self.remember(PluginError::Host(HostError::failed(format!(
                "`{service}` for robot `{}` returned {} values; its configurations have {}",
                self.robot,
                q.len(),
                out.len()
            )))),
            Err(error) => self.remember(error.into()),
        }
    }
}

impl Space for HostSpace<'_> {
    fn sample(&self, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        if self.failed() {
            return;
        }
        // Sampling happens once per iteration, so this is where a long search notices.
        if self.host.is_cancelled() {
            self.remember(PluginError::Cancelled);
            return;
        }
        // The host draws the configuration; this planner's own generator draws only the seed,
        // so the request's seed still decides the whole search.
        let seed = rng.next_u64();
        let answer = self.host.sample_configuration(self.robot, seed);
        self.write_configuration("sample_configuration", answer, out);
    }

    fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        // Infinitely far once failed: nothing is reached and no waypoints merge.
        self.ask(f64::INFINITY, || self.host.distance(self.robot, a, b))
    }

    fn distance_form(&self, q: &[f64]) -> Vec<f64> {
        // Any form will do once failed: `nearest` then answers without reading it.
        self.ask(Vec::new(), || self.host.distance_form(self.robot, q))
    }

    fn nearest(&self, forms: &[Vec<f64>], form: &[f64]) -> usize {
        // The root once failed; the search stops before it grows from it.
        self.ask(0, || self.host.nearest(self.robot, forms, form))
    }

    fn interpolate(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
        if self.failed() {
            return;
        }
        let answer = self.host.interpolate(self.robot, a, b, t);
        self.write_configuration("interpolate", answer, out);
    }

    fn is_valid(&self, q: &[f64]) -> bool {
        q.len() == self.dimension
            && self.ask(false, || self.host.configuration_is_valid(self.robot, q))
    }

    /// One step: with [`edge_is_valid`](Self::edge_is_valid) overridden, lamp-rrt's search and
    /// shortcutting never sub-step an edge themselves; the host checks every edge whole, at its
    /// own resolution, in one call.
    fn edge_steps(&self, _a: &[f64], _b: &[f64]) -> usize {
        1
    }

    fn edge_is_valid(&self, a: &[f64], b: &[f64]) -> bool {
        self.ask(false, || self.host.edge_is_valid(self.robot, a, b))
    }

    fn should_stop(&self) -> bool {
        self.failed()
    }
}
