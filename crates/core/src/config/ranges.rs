//! The range checks and the report of a configuration's mistakes.
//!
//! [`Config::validate`] applies every section's rules (each section's `validate` method, next to
//! its struct) and collects every mistake they find ([`Mistakes`]), each with the key it concerns;
//! a rule that relates keys runs once the keys it relates passed their own checks, so that one
//! wrong value is reported once. [`report`] places each mistake at the line or `--set` override
//! where its key was written ([`GivenKeys`]) and lists them all in that order in one
//! [`Error::Config`]: one mistake as it always read, several under a line that counts them.

use super::given::{GivenKeys, Place};
use super::Config;
use crate::error::Error;

/// One mistake: the key it concerns and the message that names it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Mistake {
    /// The key (`section.name`), a section, or empty when the mistake is no key's.
    pub key: String,
    /// The message.
    pub message: String,
    /// Where it was written, when known where the mistake was found; the message then says it
    /// already. `None`: placed by the key ([`report`]).
    pub place: Option<Place>,
}

impl Mistake {
    /// A mistake of `key`, to be placed where the key was written.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            message: message.into(),
            place: None,
        }
    }

    /// A mistake whose message says its place (`place`) already.
    pub fn at(key: impl Into<String>, message: impl Into<String>, place: Place) -> Self {
        Self {
            key: key.into(),
            message: message.into(),
            place: Some(place),
        }
    }

    /// The place of the mistake and its text with the place: the place of its key when given,
    /// else the first given key its message names, else the first given key of its section.
    fn placed(self, given: &GivenKeys) -> (Place, String) {
        if let Some(place) = self.place {
            return (place, self.message);
        }
        let section = format!("{}.", self.key);
        let place = given
            .get(&self.key)
            .or_else(|| given.iter().find(|k| names(&self.message, &k.key)))
            .or_else(|| given.iter().find(|k| k.key.starts_with(&section)))
            .map_or(Place::Default, |k| k.place);
        let phrase = place.phrase(given.overrides());
        let text = match phrase.trim_start() {
            "" => self.message,
            p => format!("{} ({p})", self.message),
        };
        (place, text)
    }
}

/// Whether `message` names `key` as a whole (`time.dt`, not `time.dtx`).
fn names(message: &str, key: &str) -> bool {
    message.match_indices(key).any(|(i, _)| {
        let after = message[i + key.len()..].chars().next();
        let before = message[..i].chars().next_back();
        let part = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.');
        !part(after) && !part(before)
    })
}

/// The mistakes a configuration's rules found, in the order found.
#[derive(Debug, Default)]
pub(super) struct Mistakes(Vec<Mistake>);

impl Mistakes {
    /// Keeps the mistake of a check, if any; whether the check passed.
    pub fn check(&mut self, result: Result<(), Mistake>) -> bool {
        match result {
            Ok(()) => true,
            Err(m) => {
                self.0.push(m);
                false
            }
        }
    }

    /// Keeps a mistake.
    pub fn keep(&mut self, mistake: Mistake) {
        self.0.push(mistake);
    }

    /// Keeps a mistake of `key`.
    pub fn push(&mut self, key: &str, message: impl Into<String>) {
        self.0.push(Mistake::new(key, message));
    }

    /// Mistakes found so far.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// The mistakes.
    pub fn into_vec(self) -> Vec<Mistake> {
        self.0
    }
}

impl Config {
    /// Checks every value against its allowed range, section by section (each section's rules
    /// are its `validate` method, next to its struct); the error lists every mistake, each
    /// message naming its key.
    pub fn validate(&self) -> Result<(), Error> {
        report(self.mistakes(), &GivenKeys::default(), None)
    }

    /// Every mistake of the values, in the order of the sections.
    pub(super) fn mistakes(&self) -> Vec<Mistake> {
        let mut m = Mistakes::default();
        let before = m.len();
        self.geometry.validate(&mut m);
        // the mesh's sizes are measured against a valid geometry only
        let geometry = (m.len() == before).then_some(&self.geometry);
        self.mesh.validate(geometry, &mut m);
        self.material.validate(&mut m);
        self.gravity.validate(&mut m);
        self.initial.validate(&mut m);
        self.time.validate(&mut m);
        self.solver.validate(&mut m);
        self.torque.validate(&mut m);
        self.wall.validate(&mut m);
        self.contact.validate(&self.wall, self.time.scheme, &mut m);
        self.output.validate(&mut m);
        self.model.validate(self, &mut m);
        m.into_vec()
    }
}

/// `Ok` without mistakes; else the one [`Error::Config`] listing them all, each placed by `given`
/// (see [`Mistake::placed`]), in the order of their places: by line, then the `--set` overrides in
/// their order, then the mistakes of keys no one wrote. `file` (the configuration file's name)
/// starts the message.
pub(super) fn report(mistakes: Vec<Mistake>, given: &GivenKeys, file: Option<&str>) -> Result<(), Error> {
    let mut placed: Vec<(Place, String)> = mistakes.into_iter().map(|m| m.placed(given)).collect();
    placed.sort_by_key(|(place, _)| *place);
    let body = match placed.as_slice() {
        [] => return Ok(()),
        [(_, one)] => one.clone(),
        many => format!(
            "{} mistakes, in the order written (by line, then the --set overrides):\n  {}",
            many.len(),
            many.iter().map(|(_, m)| m.as_str()).collect::<Vec<_>>().join("\n  ")
        ),
    };
    Err(Error::Config(match file {
        Some(f) => format!("{f}: {body}"),
        None => body,
    }))
}

/// The mistake of `key = value` outside what is `allowed`.
pub(super) fn range(key: &str, value: f64, allowed: &str) -> Mistake {
    Mistake::new(key, format!("{key} = {value}: allowed {allowed}"))
}

pub(super) fn finite(key: &str, v: f64) -> Result<(), Mistake> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, "a finite number"))
    }
}

pub(super) fn positive(key: &str, v: f64, unit: &str) -> Result<(), Mistake> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, &format!("a finite value > 0 {unit}")))
    }
}

pub(super) fn non_negative(key: &str, v: f64, unit: &str) -> Result<(), Mistake> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, &format!("a finite value >= 0 {unit}")))
    }
}

pub(super) fn within(key: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), Mistake> {
    if v >= lo && v <= hi {
        Ok(())
    } else {
        Err(range(key, v, &format!("{lo} to {hi} {unit}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mistake_of_the_values_is_reported_each_naming_its_key() {
        let mut cfg = Config::default();
        cfg.time.dt = 0.0;
        cfg.material.poisson_ratio = 0.7;
        cfg.output.max_frames = 1;
        let e = cfg.validate().unwrap_err().to_string();
        assert!(e.contains("3 mistakes"), "{e}");
        for key in ["time.dt = 0", "material.poisson_ratio = 0.7", "output.max_frames = 1"] {
            assert!(e.contains(key), "{key} missing in {e}");
        }
        // a relation of two keys is not checked when one of them is wrong on its own
        let mut cfg = Config::default();
        cfg.geometry.head_radius = -1.0;
        let e = cfg.validate().unwrap_err().to_string();
        assert!(
            !e.contains("mistakes") && e.contains("geometry.head_radius = -1"),
            "{e}"
        );
    }

    #[test]
    fn a_message_names_a_key_only_as_a_whole() {
        assert!(names("time.dt = 0: allowed", "time.dt"));
        assert!(names("needs time.dt, so", "time.dt"));
        assert!(!names("time.dtx = 0", "time.dt"));
        assert!(!names("xtime.dt = 0", "time.dt"));
    }
}
