//! The `plugins` block.

use std::collections::BTreeMap;

use super::Checker;
use super::Dimension;
use crate::ast::{Item, Name, OptionEntry, Plugin, PluginRef, Value};
use crate::diagnostics::{SpecError, at, did_you_mean};
use crate::source::Span;
use lamp_spec::limits;
use lamp_spec::{OptionKind, OptionRule, OptionValue, PluginChoice, PluginKind, PluginSource};

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
                // A built-in plugin's options are known; a library's pass through, except those
                // the runtime reads itself. An unknown built-in is reported above already.
                let own: Option<&[OptionRule]> = match &plugin.source {
                    PluginRef::Builtin(name) => match kind.builtin_options(&name.text) {
                        Some(own) => Some(own),
                        None => continue,
                    },
                    PluginRef::Library(_) => None,
                };
                for option in &plugin.options {
                    if !self.declare(&mut keys, "option", &option.key) {
                        continue;
                    }
                    let key = option.key.text.as_str();
                    let rules = kind.runtime_options().iter().chain(own.unwrap_or_default());
                    let value = match rules.clone().find(|rule| rule.name == key) {
                        Some(rule) => self.plugin_option(kind, rule, option),
                        None if own.is_none() => self.option_value(&option.value),
                        None => {
                            let names: Vec<&str> = rules.map(|rule| rule.name).collect();
                            self.unknown_option(plugin, &option.key, &names);
                            None
                        }
                    };
                    if let Some(value) = value {
                        options.insert(key.to_string(), value);
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

impl Checker<'_> {
    /// An option a rule knows, checked against it: its kind of value, its unit and its range.
    fn plugin_option(
        &mut self,
        kind: PluginKind,
        rule: &OptionRule,
        option: &OptionEntry,
    ) -> Option<OptionValue> {
        let what = format!("`{}` of the {}", rule.name, kind_name(kind));
        let quantity = match (&option.value, rule.kind) {
            (Value::Text(text), OptionKind::Text) => {
                return Some(OptionValue::Text(text.text.clone()));
            }
            (Value::Word(word), OptionKind::Text) => {
                return Some(OptionValue::Word(word.text.clone()));
            }
            (Value::Quantity(quantity), kind) if kind != OptionKind::Text => quantity,
            (_, expected) => {
                let expected = match expected {
                    OptionKind::Text => "text in quotes",
                    OptionKind::Seconds => "a duration, for example `30 s`",
                    OptionKind::Length(_) => "a length, for example `0.25 m`",
                    OptionKind::Resolution => "a length or an angle, for example `0.01 rad`",
                    OptionKind::Count(_) | OptionKind::Number(_) => "a number",
                };
                let span = option.key.span;
                self.require(false, span, &what, expected);
                return None;
            }
        };
        let span = quantity.span;
        match rule.kind {
            OptionKind::Seconds => {
                let seconds = self.measure(quantity, Dimension::Duration)?;
                self.limited(seconds, span, &what, &limits::SECONDS).map(OptionValue::Duration)
            }
            OptionKind::Count(limit) | OptionKind::Number(limit) => {
                let value = self.plain(quantity, &what)?;
                self.limited(value, span, &what, &limit).map(OptionValue::Number)
            }
            OptionKind::Length(limit) => {
                let length = self.measure(quantity, Dimension::Length)?;
                self.limited(length, span, &what, &limit).map(OptionValue::Length)
            }
            OptionKind::Resolution => self.resolution(quantity, &what),
            OptionKind::Text => None,
        }
    }

    /// A checking resolution: a length or an angle, each within its own range.
    fn resolution(&mut self, quantity: &crate::ast::Quantity, what: &str) -> Option<OptionValue> {
        let dimension = match quantity.unit.map(|(unit, _)| super::units::unit_info(unit).0) {
            Some(Dimension::Angle) => Dimension::Angle,
            // A duration or no unit is reported as a missing length.
            _ => Dimension::Length,
        };
        if let Some((unit, unit_span)) = quantity.unit
            && super::units::unit_info(unit).0 == Dimension::Duration
        {
            self.report(at(unit_span, |at| SpecError::WrongUnit {
                unit: super::units::unit_text(unit).to_string(),
                dimension: "a length or an angle",
                allowed: "m, cm, mm, deg, rad",
                at,
            }));
            return None;
        }
        let value = self.measure(quantity, dimension)?;
        if dimension == Dimension::Angle {
            self.limited(value, quantity.span, what, &limits::ANGULAR_RESOLUTION)
                .map(OptionValue::Angle)
        } else {
            self.limited(value, quantity.span, what, &limits::LINEAR_RESOLUTION)
                .map(OptionValue::Length)
        }
    }

    /// Reports an option a built-in plugin does not read.
    fn unknown_option(&mut self, plugin: &Plugin, key: &Name, names: &[&str]) {
        let plugin_name = match &plugin.source {
            PluginRef::Builtin(name) => name.text.as_str(),
            PluginRef::Library(path) => path.text.as_str(),
        };
        let help = did_you_mean(&key.text, names.iter().copied()).unwrap_or_else(|| {
            format!(
                "The built-in `{plugin_name}` reads only the options listed; a shared-library plugin receives any option."
            )
        });
        self.report(at(key.span, |at| SpecError::UnknownWord {
            what: "plugin option",
            word: key.text.clone(),
            at,
            expected: names.join(", "),
            help: Some(help),
        }));
    }
}

/// A plugin kind as a message names it.
fn kind_name(kind: PluginKind) -> &'static str {
    match kind {
        PluginKind::Planner => "planner",
        PluginKind::Refiner => "refiner",
        PluginKind::Motion => "motion planner",
    }
}
