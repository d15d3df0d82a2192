//! A numeric setting's allowed interval, written once: validation checks values against
//! it, and the documentation test compares it with what docs/settings.md states. A value
//! and its `Bound` flow in; the user's message flows out on failure:
//! `render.width: 0 is out of range (1 to 16384)`.

/// The closed interval a numeric setting must lie in, with the dotted key it belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// The dotted key the interval belongs to, such as `render.width`.
    pub key: &'static str,
    /// Smallest allowed value.
    pub min: f32,
    /// Largest allowed value.
    pub max: f32,
}

impl Bound {
    /// The interval `min..=max` for `key`.
    pub const fn new(key: &'static str, min: f32, max: f32) -> Bound {
        Bound { key, min, max }
    }

    /// Whether `value` is finite and inside the interval.
    pub fn contains(&self, value: f32) -> bool {
        value.is_finite() && (self.min..=self.max).contains(&value)
    }

    /// `Ok` inside the interval; otherwise the message naming the key, the value and the
    /// interval.
    pub fn check(&self, value: f32) -> Result<(), String> {
        if self.contains(value) {
            Ok(())
        } else {
            Err(format!(
                "{}: {} is out of range ({} to {})",
                self.key,
                number(value),
                number(self.min),
                number(self.max)
            ))
        }
    }
}

/// A number as a reader would write it: 1e-40, not forty zeros.
pub(crate) fn number(v: f32) -> String {
    if v != 0.0 && v.is_finite() && !(1.0e-4..1.0e7).contains(&v.abs()) { format!("{v:e}") } else { format!("{v}") }
}
