//! The `plugins` block.

use std::collections::BTreeMap;

use super::Checker;
use crate::ast::{Item, PluginRef};
use crate::diagnostics::{SpecError, at, did_you_mean};
use crate::source::Span;
use lamp_spec::{PluginChoice, PluginKind, PluginSource};

impl Checker<'_> {
    pub(crate) fn plugins(&mut self, items: &[Item]) -> Option<lamp_spec::Plugins> {
        let errors_before = self.diagnostics.len();
        let mut chosen: BTreeMap<PluginKind, PluginChoice> = BTreeMap::new();
        let mut first: BTreeMap<PluginKind, Option<Span>> = BTreeMap::new();
        for item in items {
            let Item::Plugins { plugins } = item else { continue };
            for plugin in plugins {
                let kind = match plugin.kind.text.as_str() {
                    "planner" => PluginKind::Planner,
                    "refiner" => PluginKind::Refiner,
                    _ => PluginKind::Motion,
                };
                let slot = first.entry(kind).or_default();
                let mut seen = *slot;
                let is_first =
                    self.once(&mut seen, &format!("the {} plugin", plugin.kind.text), plugin.span);
                *slot = seen;
                if !is_first {
                    continue;
                }
                let source = match &plugin.source {
                    PluginRef::Builtin(name) => {
                        if kind.builtins().contains(&name.text.as_str()) {
                            Some(PluginSource::Builtin(name.text.clone()))
                        } else {
                            self.report(at(name.span, |at| SpecError::UnknownWord {
                                what: "built-in plugin",
                                word: name.text.clone(),
                                at,
                                expected: kind.builtins().join(", "),
                                help: did_you_mean(&name.text, kind.builtins().iter().copied()).or(
                                    Some(
                                        "A shared-library plugin is named by its path in quotes."
                                            .to_string(),
                                    ),
                                ),
                            }));
                            None
                        }
                    }
                    PluginRef::Library(path) => {
                        self.existing_file(path, "plugin library").map(PluginSource::Library)
                    }
                };
                let mut options = BTreeMap::new();
                let mut keys = BTreeMap::new();
                for option in &plugin.options {
                    if self.declare(&mut keys, "option", &option.key)
                        && let Some(value) = self.option_value(&option.value)
                    {
                        options.insert(option.key.text.clone(), value);
                    }
                }
                if let Some(source) = source {
                    chosen.insert(kind, PluginChoice { source, options });
                }
            }
        }
        let mut take =
            |kind| chosen.remove(&kind).unwrap_or_else(|| PluginChoice::default_for(kind));
        (self.diagnostics.len() == errors_before).then(|| lamp_spec::Plugins {
            planner: take(PluginKind::Planner),
            refiner: take(PluginKind::Refiner),
            motion: take(PluginKind::Motion),
        })
    }
}
