//! Numbers with units: conversion to SI and the checks that go with it.

use nalgebra::{Translation3, UnitQuaternion};

use super::Checker;
use crate::ast::{Pose, Quantity, Unit, Vector};
use crate::diagnostics::{SpecError, at};
use crate::source::Span;
use lamp_spec::limits::{self, Limit, Problem};

/// What a number measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Dimension {
    Length,
    Angle,
    Duration,
    Frequency,
}

impl Dimension {
    fn name(self) -> &'static str {
        match self {
            Dimension::Length => "a length",
            Dimension::Angle => "an angle",
            Dimension::Duration => "a duration",
            Dimension::Frequency => "a frequency",
        }
    }

    fn example(self) -> &'static str {
        match self {
            Dimension::Length => "0.15 m",
            Dimension::Angle => "90 deg",
            Dimension::Duration => "30 s",
            Dimension::Frequency => "50 Hz",
        }
    }

    fn allowed(self) -> &'static str {
        match self {
            Dimension::Length => "m, cm, mm",
            Dimension::Angle => "deg, rad",
            Dimension::Duration => "s, ms",
            Dimension::Frequency => "Hz",
        }
    }
}

/// The dimension of a unit and its factor to SI.
pub(crate) fn unit_info(unit: Unit) -> (Dimension, f64) {
    match unit {
        Unit::Metre => (Dimension::Length, 1.0),
        Unit::Centimetre => (Dimension::Length, 0.01),
        Unit::Millimetre => (Dimension::Length, 0.001),
        Unit::Degree => (Dimension::Angle, std::f64::consts::PI / 180.0),
        Unit::Radian => (Dimension::Angle, 1.0),
        Unit::Second => (Dimension::Duration, 1.0),
        Unit::Millisecond => (Dimension::Duration, 0.001),
        Unit::Hertz => (Dimension::Frequency, 1.0),
    }
}

pub(crate) fn unit_text(unit: Unit) -> &'static str {
    match unit {
        Unit::Metre => "m",
        Unit::Centimetre => "cm",
        Unit::Millimetre => "mm",
        Unit::Degree => "deg",
        Unit::Radian => "rad",
        Unit::Second => "s",
        Unit::Millisecond => "ms",
        Unit::Hertz => "Hz",
    }
}

impl Checker<'_> {
    /// The SI factor for a unit that must measure `dimension`; reports a missing or wrong unit.
    fn factor(
        &mut self,
        unit: Option<(Unit, Span)>,
        dimension: Dimension,
        whole: Span,
    ) -> Option<f64> {
        let Some((unit, unit_span)) = unit else {
            self.report(at(whole, |at| SpecError::UnitRequired {
                dimension: dimension.name(),
                example: dimension.example(),
                at,
            }));
            return None;
        };
        let (actual, factor) = unit_info(unit);
        if actual != dimension {
            self.report(at(unit_span, |at| SpecError::WrongUnit {
                unit: unit_text(unit).to_string(),
                dimension: dimension.name(),
                allowed: dimension.allowed(),
                at,
            }));
            return None;
        }
        Some(factor)
    }

    /// A quantity of the given dimension, in SI units.
    pub(crate) fn measure(&mut self, quantity: &Quantity, dimension: Dimension) -> Option<f64> {
        let factor = self.factor(quantity.unit, dimension, quantity.span)?;
        self.finite(quantity.value * factor, quantity.span)
    }

    /// `value` unless it is infinite or not a number (a literal too large for a float), which
    /// is reported: nothing downstream can compute with it.
    pub(crate) fn finite(&mut self, value: f64, span: Span) -> Option<f64> {
        self.require(
            value.is_finite(),
            span,
            "the number",
            "a finite number (at most about 1.8e308)",
        )
        .then_some(value)
    }

    /// A length that must be strictly positive.
    pub(crate) fn positive_length(&mut self, quantity: &Quantity, what: &str) -> Option<f64> {
        let value = self.measure(quantity, Dimension::Length)?;
        self.require(value > 0.0 && value.is_finite(), quantity.span, what, "a positive length")
            .then_some(value)
    }

    /// A vector of lengths, in metres.
    pub(crate) fn length_vector(&mut self, vector: &Vector) -> Option<[f64; 3]> {
        let factor = self.factor(vector.unit, Dimension::Length, vector.span)?;
        self.finite_vector(vector, factor)
    }

    /// A vector's values times `factor`, each checked to be finite.
    fn finite_vector(&mut self, vector: &Vector, factor: f64) -> Option<[f64; 3]> {
        let mut values = [0.0; 3];
        let mut all_finite = true;
        for ((out, value), span) in values.iter_mut().zip(vector.values).zip(vector.number_spans) {
            match self.finite(value * factor, span) {
                Some(value) => *out = value,
                None => all_finite = false,
            }
        }
        all_finite.then_some(values)
    }

    /// A pose: position with a length unit, optional roll-pitch-yaw with an angle unit.
    /// The rotation is `Rz(yaw) · Ry(pitch) · Rx(roll)` (fixed-axis x, then y, then z).
    pub(crate) fn pose(&mut self, pose: &Pose) -> Option<lamp_spec::Pose> {
        let position = self.length_vector(&pose.position);
        let rotation = match &pose.rotation {
            None => Some(UnitQuaternion::identity()),
            Some(rpy) => self.factor(rpy.unit, Dimension::Angle, rpy.span).and_then(|factor| {
                let [roll, pitch, yaw] = self.finite_vector(rpy, factor)?;
                Some(UnitQuaternion::from_euler_angles(roll, pitch, yaw))
            }),
        };
        let [x, y, z] = position?;
        Some(lamp_spec::Pose::from_parts(Translation3::new(x, y, z), rotation?))
    }

    /// A pose of a structure object relative to its anchor, or a structure goal's offset: a pose
    /// whose every coordinate [`limits::STRUCTURE_OFFSET`] allows, each refused at its number.
    pub(crate) fn structure_pose(&mut self, pose: &Pose, what: &str) -> Option<lamp_spec::Pose> {
        let checked = self.pose(pose)?;
        let coordinates = checked.translation.vector;
        let mut within = true;
        for (coordinate, span) in coordinates.iter().zip(pose.position.number_spans) {
            within &= self.limited(*coordinate, span, what, &limits::STRUCTURE_OFFSET).is_some();
        }
        within.then_some(checked)
    }

    /// A plain number (no unit allowed).
    pub(crate) fn plain(&mut self, quantity: &Quantity, what: &str) -> Option<f64> {
        if let Some((_, unit_span)) = quantity.unit {
            self.report(at(unit_span, |at| SpecError::UnexpectedUnit {
                what: what.to_string(),
                at,
            }));
            return None;
        }
        Some(quantity.value)
    }

    /// A whole number at least `minimum`.
    pub(crate) fn count(&mut self, quantity: &Quantity, what: &str, minimum: u32) -> Option<u32> {
        let value = self.plain(quantity, what)?;
        self.whole(value, quantity.span, what, minimum)
    }

    /// A whole number `value` (already unit-free) at least `minimum`.
    pub(crate) fn whole(
        &mut self,
        value: f64,
        span: Span,
        what: &str,
        minimum: u32,
    ) -> Option<u32> {
        if value.fract() != 0.0 || !value.is_finite() {
            self.report(at(span, |at| SpecError::NotInteger { what: what.to_string(), at }));
            return None;
        }
        // Both bounds: a value past the top refused as "must be zero or more" names no cause.
        let expected = format!("a whole number from {minimum} to {} (2^32 - 1)", u32::MAX);
        if value < f64::from(minimum) || value > f64::from(u32::MAX) {
            self.report(at(span, |at| SpecError::OutOfRange {
                what: what.to_string(),
                expected,
                at,
            }));
            return None;
        }
        // Checked above: a whole number within the u32 range.
        Some(value as u32)
    }

    /// A plain number in (0, 1].
    pub(crate) fn fraction_open(&mut self, quantity: &Quantity, what: &str) -> Option<f64> {
        let value = self.plain(quantity, what)?;
        self.require(
            value > 0.0 && value <= 1.0,
            quantity.span,
            what,
            "greater than 0 and at most 1",
        )
        .then_some(value)
    }

    /// A plain number in [0, 1].
    pub(crate) fn fraction_closed(&mut self, quantity: &Quantity, what: &str) -> Option<f64> {
        let value = self.plain(quantity, what)?;
        self.require((0.0..=1.0).contains(&value), quantity.span, what, "between 0 and 1")
            .then_some(value)
    }

    /// Reports `what` out of range unless `ok`.
    pub(crate) fn require(&mut self, ok: bool, span: Span, what: &str, expected: &str) -> bool {
        if !ok {
            self.report(at(span, |at| SpecError::OutOfRange {
                what: what.to_string(),
                expected: expected.to_string(),
                at,
            }));
        }
        ok
    }

    /// `value` (in SI units) if `limit` allows it; else reports it as not whole or out of range,
    /// with the range the limit allows (the same words `lampc`'s flags use).
    pub(crate) fn limited(
        &mut self,
        value: f64,
        span: Span,
        what: &str,
        limit: &Limit,
    ) -> Option<f64> {
        let error = match limit.check(value) {
            Ok(value) => return Some(value),
            Err(error) => error,
        };
        let what = what.to_string();
        self.report(at(span, |at| match error.problem {
            Problem::NotWhole => SpecError::NotInteger { what, at },
            Problem::NotFinite | Problem::OutOfRange => {
                SpecError::OutOfRange { what, expected: error.expected, at }
            }
        }));
        None
    }

    /// A whole number `limit` allows.
    pub(crate) fn limited_count(
        &mut self,
        quantity: &Quantity,
        what: &str,
        limit: &Limit,
    ) -> Option<u32> {
        let value = self.plain(quantity, what)?;
        let value = self.limited(value, quantity.span, what, limit)?;
        // The limit allows only whole numbers up to a u32 maximum.
        u32::try_from(value as u64).ok()
    }
}
