//! The cases of a sweep: `--vary KEY=VALUES` arguments, `--zip`, and sweep files, expanded into
//! a [`Plan`] (an ordered list of cases, each a set of configuration overrides).
//!
//! VALUES takes three forms:
//!
//! | form | example | values |
//! |---|---|---|
//! | list | `1e6,1e7,2.1e11` | as typed (numbers, `true`, quoted or bare strings) |
//! | linear range | `10:60:6` (start:stop:count) | `start + (stop − start) i/(count − 1)` |
//! | log range | `1e6..2.1e11:8` (start..stop:count) | `start (stop/start)^(i/(count − 1))`, start, stop > 0 |
//!
//! Range values are rounded to 12 significant digits (so `1e6..1e9:4` gives `1e7`, not
//! `9999999.999999998`) and the end points are exactly those typed. Several `--vary` form the full
//! grid (the first key varies slowest); with `--zip` they are paired instead and must have the same
//! number of values.
//!
//! A sweep file keeps a study:
//!
//! ```toml
//! config = "base.toml"          # optional, relative to this file (`--config` overrides it)
//! set = ["time.end = 2"]        # optional overrides for every case
//! zip = false                   # optional
//!
//! [vary]                        # a grid (or zip), in the order written here
//! material.youngs_modulus = "1e6..2.1e11:8"
//! initial.angle_deg = [10, 20, 30]
//! ```
//!
//! or, for cases that are no grid, an explicit list (keys not named in a case keep the base value):
//!
//! ```toml
//! [[case]]
//! material.youngs_modulus = 1e6
//! [[case]]
//! material.youngs_modulus = 2.1e11
//! initial.angle_deg = 45
//! ```
//!
//! `[[case]]` and `[vary]` (and `--vary`) combine like several `--vary`: the case list is one
//! "key" of the grid.

use std::path::{Path, PathBuf};

use crate::Error;

/// The allowed forms of VALUES, for error messages.
pub const VALUE_FORMS: &str = "a list `1e6,1e7,2.1e11`, a linear range `10:60:6` (start:stop:count) \
                               or a log range `1e6..2.1e11:8` (start..stop:count, start and stop > 0)";

/// The cases of a sweep: `cases[k][j]` is the value of `keys[j]` in case `k`, as a TOML literal
/// (what `--set key=literal` takes), or `None` where the case keeps the base value.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Varied configuration keys (`material.youngs_modulus`), in column order.
    pub keys: Vec<String>,
    /// One entry per case, one value per key.
    pub cases: Vec<Vec<Option<String>>>,
}

impl Plan {
    /// The plan with one case and no keys (the neutral element of [`Plan::product`]).
    pub fn unit() -> Self {
        Self {
            keys: Vec::new(),
            cases: vec![Vec::new()],
        }
    }

    /// One key taking each of `values` (TOML literals) in turn.
    pub fn single(key: &str, values: Vec<String>) -> Self {
        Self {
            keys: vec![key.to_string()],
            cases: values.into_iter().map(|v| vec![Some(v)]).collect(),
        }
    }

    /// Number of cases.
    pub fn len(&self) -> usize {
        self.cases.len()
    }

    /// Whether there are no cases.
    pub fn is_empty(&self) -> bool {
        self.cases.is_empty()
    }

    /// Every case of `self` with every case of `other` (`self` varies slowest).
    pub fn product(self, other: Plan) -> Result<Plan, Error> {
        self.check_disjoint(&other)?;
        let mut cases = Vec::with_capacity(self.len() * other.len());
        for a in &self.cases {
            for b in &other.cases {
                cases.push(a.iter().chain(b).cloned().collect());
            }
        }
        Ok(Plan {
            keys: self.keys.into_iter().chain(other.keys).collect(),
            cases,
        })
    }

    /// Case k of `self` with case k of `other`; both must have as many cases.
    pub fn zip(self, other: Plan) -> Result<Plan, Error> {
        self.check_disjoint(&other)?;
        if self.keys.is_empty() {
            return Ok(other);
        }
        if self.len() != other.len() {
            return Err(Error::Config(format!(
                "--zip: {} has {} values but {} has {}; zipped keys need the same number of values",
                self.keys.join(", "),
                self.len(),
                other.keys.join(", "),
                other.len()
            )));
        }
        let cases = self
            .cases
            .iter()
            .zip(&other.cases)
            .map(|(a, b)| a.iter().chain(b).cloned().collect())
            .collect();
        Ok(Plan {
            keys: self.keys.into_iter().chain(other.keys).collect(),
            cases,
        })
    }

    fn check_disjoint(&self, other: &Plan) -> Result<(), Error> {
        match self.keys.iter().find(|k| other.keys.contains(k)) {
            Some(k) => Err(Error::Config(format!(
                "sweep: the key {k} is varied twice; give each key one --vary (or one sweep-file entry)"
            ))),
            None => Ok(()),
        }
    }

    /// The `key=literal` overrides of case `k` (keys the case leaves alone are skipped).
    pub fn overrides(&self, k: usize) -> Vec<String> {
        self.keys
            .iter()
            .zip(&self.cases[k])
            .filter_map(|(key, v)| v.as_ref().map(|v| format!("{key}={v}")))
            .collect()
    }

    /// The text of a sweep folder's `cases.csv`: `case,<keys…>`, then the case number and the
    /// literals of each case (empty where the case keeps the base value).
    pub fn to_cases_csv(&self) -> String {
        let mut text = std::iter::once("case".to_string())
            .chain(self.keys.iter().map(|k| super::case::csv_field(k)))
            .collect::<Vec<_>>()
            .join(",");
        text.push('\n');
        for (k, values) in self.cases.iter().enumerate() {
            let cells: Vec<String> = std::iter::once(k.to_string())
                .chain(
                    values
                        .iter()
                        .map(|v| v.as_deref().map(super::case::csv_field).unwrap_or_default()),
                )
                .collect();
            text.push_str(&cells.join(","));
            text.push('\n');
        }
        text
    }

    /// Reads the plan back from the text of a sweep folder's `cases.csv` ([`Plan::to_cases_csv`]);
    /// errors name the file (`name`) and the line.
    pub fn from_cases_csv(text: &str, name: &str) -> Result<Plan, Error> {
        let err = |m: String| Error::Input(format!("{name}: {m}"));
        let mut lines = text.lines();
        let head = super::case::split_csv_line(lines.next().unwrap_or_default()).map_err(&err)?;
        if head.first().map(String::as_str) != Some("case") {
            return Err(err("the header must start with `case`".into()));
        }
        let keys = head[1..].to_vec();
        let mut cases = Vec::new();
        for (i, line) in lines.enumerate() {
            let cells = super::case::split_csv_line(line).map_err(&err)?;
            if cells.len() != head.len() || cells[0] != i.to_string() {
                return Err(err(format!(
                    "line {}: expected case {i} and {} values",
                    i + 2,
                    keys.len()
                )));
            }
            cases.push(cells[1..].iter().map(|c| (!c.is_empty()).then(|| c.clone())).collect());
        }
        Ok(Plan { keys, cases })
    }

    /// `(key, value as shown in summary.csv)` of case `k`: strings without their quotes, numbers as
    /// typed, an empty value where the case keeps the base value.
    pub fn shown(&self, k: usize) -> Vec<(String, String)> {
        self.keys
            .iter()
            .zip(&self.cases[k])
            .map(|(key, v)| (key.clone(), v.as_deref().map(shown_value).unwrap_or_default()))
            .collect()
    }
}

/// A TOML literal as shown in a table: a string's content, anything else as written.
pub fn shown_value(literal: &str) -> String {
    match format!("v = {literal}").parse::<toml::Table>() {
        Ok(t) => match t.get("v") {
            Some(toml::Value::String(s)) => s.clone(),
            _ => literal.to_string(),
        },
        Err(_) => literal.to_string(),
    }
}

/// A number as a TOML literal that reads back as the same `f64`: integral values below 10⁶ as
/// integers (also accepted by integer keys), others in the shortest round-trip form, with an
/// exponent outside `1e-4 ≤ |v| < 1e6` (`2.1e11`, `1.5e-7`, readable in the summary).
pub fn number_literal(v: f64) -> String {
    let a = v.abs();
    if v == v.trunc() && a < 1e6 {
        format!("{}", v as i64)
    } else if (1e-4..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Rounds to 12 significant digits (range values: `1e7`, not `9999999.999999998`).
fn round12(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// Parses one `--vary KEY=VALUES` argument (see the module documentation) into a one-key plan.
pub fn parse_vary(arg: &str) -> Result<Plan, Error> {
    let bad = |why: &str| {
        Error::Config(format!(
            "--vary {arg}: {why}; expected KEY=VALUES with a configuration key (any depth, e.g. \
             material.youngs_modulus) and VALUES {VALUE_FORMS}"
        ))
    };
    let (key, values) = arg.split_once('=').ok_or_else(|| bad("no `=`"))?;
    let key = key.trim();
    if key.split('.').count() < 2 || key.split('.').any(|p| p.trim().is_empty()) {
        return Err(bad(&format!("`{key}` is not a section.name key")));
    }
    let values = parse_values(values.trim()).map_err(|why| bad(&why))?;
    Ok(Plan::single(key, values))
}

/// Expands VALUES (one of [`VALUE_FORMS`]) into TOML literals; the error says what is wrong.
pub fn parse_values(text: &str) -> Result<Vec<String>, String> {
    let count = |c: &str| -> Result<usize, String> {
        match c.trim().parse::<usize>() {
            Ok(n) if n >= 2 => Ok(n),
            _ => Err(format!(
                "the count `{}` of a range must be a whole number >= 2",
                c.trim()
            )),
        }
    };
    let number = |s: &str| -> Result<f64, String> {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("`{}` is not a number", s.trim()))
    };
    if text.is_empty() {
        return Err("no values".into());
    }
    if let Some((ends, n)) = text.split_once("..").and_then(|(a, rest)| {
        let (b, n) = rest.rsplit_once(':')?;
        Some(((a, b), n))
    }) {
        let (a, b, n) = (number(ends.0)?, number(ends.1)?, count(n)?);
        if !(a > 0.0 && b > 0.0) {
            return Err(format!("a log range needs start and stop > 0 (got {a} and {b})"));
        }
        let (la, lb) = (a.ln(), b.ln());
        return Ok((0..n)
            .map(|i| match i {
                0 => a,
                i if i == n - 1 => b,
                i => round12((la + (lb - la) * i as f64 / (n - 1) as f64).exp()),
            })
            .map(number_literal)
            .collect());
    }
    if text.contains("..") {
        return Err("a log range is start..stop:count".into());
    }
    if !text.contains(',') && text.contains(':') {
        let parts: Vec<&str> = text.split(':').collect();
        let [a, b, n] = parts[..] else {
            return Err("a linear range is start:stop:count (three parts)".into());
        };
        let (a, b, n) = (number(a)?, number(b)?, count(n)?);
        let m = (n - 1) as f64;
        return Ok((0..n)
            .map(|i| match i {
                0 => a,
                i if i == n - 1 => b,
                // (a (m − i) + b i) / m keeps whole-number steps exact
                i => round12((a * (m - i as f64) + b * i as f64) / m),
            })
            .map(number_literal)
            .collect());
    }
    let items: Vec<String> = text.split(',').map(|s| s.trim().to_string()).collect();
    if items.iter().any(String::is_empty) {
        return Err("an empty item in the list".into());
    }
    Ok(items)
}

/// A sweep file (see the module documentation), read.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepFile {
    /// `config`, made relative to the current folder.
    pub config: Option<PathBuf>,
    /// `set`: overrides for every case.
    pub set: Vec<String>,
    /// `zip`.
    pub zip: bool,
    /// The plan of `[[case]]` (a list) combined with each `[vary]` entry (one plan per key, in the
    /// order written), to be combined by the caller with the `--vary` plans.
    pub plans: Vec<Plan>,
}

/// Reads a sweep file; errors name the file and the entry.
pub fn read_sweep_file(path: &Path) -> Result<SweepFile, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_sweep_file(&text, &path.display().to_string(), path.parent())
}

/// Parses the text of a sweep file named `name`; `config` is made relative to `folder`.
pub fn parse_sweep_file(text: &str, name: &str, folder: Option<&Path>) -> Result<SweepFile, Error> {
    let err = |m: String| Error::Config(format!("sweep file {name}: {m}"));
    let doc: toml::Table = text.parse().map_err(|e| err(format!("{e}")))?;
    let order = source_order(text).map_err(|e| err(format!("{e}")))?;
    let mut file = SweepFile {
        config: None,
        set: Vec::new(),
        zip: false,
        plans: Vec::new(),
    };
    for (key, value) in &doc {
        match (key.as_str(), value) {
            ("config", toml::Value::String(p)) => {
                let p = Path::new(p);
                file.config = Some(match folder {
                    Some(f) if p.is_relative() => f.join(p),
                    _ => p.to_path_buf(),
                });
            }
            ("set", toml::Value::Array(items)) => {
                for item in items {
                    let s = item
                        .as_str()
                        .ok_or_else(|| err(format!("set: `{item}` is not a string \"key = value\"")))?;
                    file.set.push(s.to_string());
                }
            }
            ("zip", toml::Value::Boolean(z)) => file.zip = *z,
            ("case", toml::Value::Array(cases)) => file.plans.insert(0, case_plan(cases, &order, &err)?),
            ("vary", toml::Value::Table(t)) => {
                for (path, value) in leaves(t, "vary", &order) {
                    let key = path.strip_prefix("vary.").unwrap_or(&path).to_string();
                    let values = match value {
                        toml::Value::String(s) => parse_values(s.trim())
                            .map_err(|why| err(format!("vary.{key} = {s:?}: {why}; VALUES is {VALUE_FORMS}")))?,
                        toml::Value::Array(items) if !items.is_empty() => items.iter().map(literal).collect(),
                        toml::Value::Array(_) => return Err(err(format!("vary.{key}: an empty list"))),
                        other => vec![literal(other)],
                    };
                    if key.split('.').count() < 2 {
                        return Err(err(format!(
                            "vary.{key}: the key must be section.name (e.g. initial.angle_deg)"
                        )));
                    }
                    file.plans.push(Plan::single(&key, values));
                }
            }
            _ => {
                return Err(err(format!(
                    "`{key}` is not one of config (a file name), set (a list of \"key = value\"), zip (true or false), \
                     [vary] or [[case]]"
                )))
            }
        }
    }
    Ok(file)
}

/// The cases of `[[case]]` tables as one plan; keys in the order they first appear.
fn case_plan(cases: &[toml::Value], order: &[String], err: &impl Fn(String) -> Error) -> Result<Plan, Error> {
    let mut keys: Vec<String> = Vec::new();
    let mut rows: Vec<Vec<(String, String)>> = Vec::new();
    for (i, case) in cases.iter().enumerate() {
        let t = case
            .as_table()
            .ok_or_else(|| err(format!("case {i} is not a table; write [[case]] tables")))?;
        let row: Vec<(String, String)> = leaves(t, &format!("case.{i}"), order)
            .into_iter()
            .map(|(path, v)| (path.splitn(3, '.').nth(2).unwrap_or_default().to_string(), literal(v)))
            .collect();
        for (k, _) in &row {
            if k.split('.').count() < 2 {
                return Err(err(format!(
                    "case {i}: `{k}` must be section.name (e.g. initial.angle_deg)"
                )));
            }
            if !keys.contains(k) {
                keys.push(k.clone());
            }
        }
        rows.push(row);
    }
    let cases = rows
        .iter()
        .map(|row| {
            keys.iter()
                .map(|k| row.iter().find(|(rk, _)| rk == k).map(|(_, v)| v.clone()))
                .collect()
        })
        .collect();
    Ok(Plan { keys, cases })
}

/// A TOML value as a `--set` literal (numbers via [`number_literal`]).
fn literal(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => number_literal(*f),
        toml::Value::Integer(i) => i.to_string(),
        other => other.to_string(),
    }
}

/// The leaves (non-table values) of `table` with their dotted paths under `prefix`, in the order
/// of `order` (the source order of every dotted path in the file; `case.N.…` for the N-th case).
fn leaves<'a>(table: &'a toml::Table, prefix: &str, order: &[String]) -> Vec<(String, &'a toml::Value)> {
    fn walk<'a>(t: &'a toml::Table, prefix: &str, out: &mut Vec<(String, &'a toml::Value)>) {
        for (k, v) in t {
            let path = format!("{prefix}.{k}");
            match v {
                toml::Value::Table(inner) => walk(inner, &path, out),
                _ => out.push((path, v)),
            }
        }
    }
    let mut out = Vec::new();
    walk(table, prefix, &mut out);
    out.sort_by_key(|(p, _)| order.iter().position(|o| o == p).unwrap_or(usize::MAX));
    out
}

/// Every leaf path of the document in source order (`toml::Table` sorts its keys; the spans of
/// the parser's own table say where each key was written). Arrays of tables count their elements:
/// `case.0.material.youngs_modulus`.
fn source_order(text: &str) -> Result<Vec<String>, toml::de::Error> {
    use toml::de::{DeTable, DeValue};
    fn walk(t: &DeTable<'_>, prefix: &str, out: &mut Vec<(usize, String)>) {
        for (k, v) in t.iter() {
            let path = if prefix.is_empty() {
                k.get_ref().to_string()
            } else {
                format!("{prefix}.{}", k.get_ref())
            };
            match v.get_ref() {
                DeValue::Table(inner) => walk(inner, &path, out),
                DeValue::Array(items) if items.iter().all(|i| i.get_ref().is_table()) && !items.is_empty() => {
                    for (i, item) in items.iter().enumerate() {
                        if let DeValue::Table(inner) = item.get_ref() {
                            walk(inner, &format!("{path}.{i}"), out);
                        }
                    }
                }
                _ => out.push((k.span().start, path)),
            }
        }
    }
    let doc = DeTable::parse(text)?;
    let mut out = Vec::new();
    walk(doc.get_ref(), "", &mut out);
    out.sort_by_key(|(start, _)| *start);
    Ok(out.into_iter().map(|(_, p)| p).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_three_value_forms_expand_as_documented() {
        assert_eq!(parse_values("1e6,1e7, 2.1e11").unwrap(), ["1e6", "1e7", "2.1e11"]);
        assert_eq!(parse_values("10:60:6").unwrap(), ["10", "20", "30", "40", "50", "60"]);
        assert_eq!(parse_values("0:1:3").unwrap(), ["0", "0.5", "1"]);
        assert_eq!(parse_values("1e6..1e9:4").unwrap(), ["1e6", "1e7", "1e8", "1e9"]);
        let log = parse_values("1e6..2.1e11:8").unwrap();
        assert_eq!(log.len(), 8);
        assert_eq!((log[0].as_str(), log[7].as_str()), ("1e6", "2.1e11"));
        assert_eq!(parse_values("neo-hookean,\"saint-venant-kirchhoff\"").unwrap().len(), 2);
        for bad in ["", "1,,2", "1:2", "1:2:1", "1:2:x", "0..1:3", "1..2", "a:b:3"] {
            assert!(parse_values(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn number_literals_read_back_as_the_same_value() {
        for v in [0.0, 1.0, -3.0, 2.1e11, 1e6, 0.1, 1.5e-7, 3e20, 1.0 / 3.0, 123456.789] {
            let text = number_literal(v);
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v} -> {text}");
            assert!(format!("v = {text}").parse::<toml::Table>().is_ok(), "{text} is TOML");
        }
    }

    #[test]
    fn vary_errors_name_the_argument_and_the_allowed_forms() {
        for bad in [
            "material.youngs_modulus",
            "youngs_modulus=1,2",
            "material.youngs_modulus=1:2",
            "a.b=1..0:3",
        ] {
            let e = parse_vary(bad).unwrap_err().to_string();
            assert!(
                e.contains(bad) && e.contains("linear range") && e.contains("log range"),
                "{e}"
            );
        }
    }

    #[test]
    fn grids_vary_the_first_key_slowest_and_zip_pairs() {
        let a = parse_vary("x.a=1,2,3").unwrap();
        let b = parse_vary("x.b=10,20").unwrap();
        let grid = Plan::unit().product(a.clone()).unwrap().product(b.clone()).unwrap();
        assert_eq!(grid.len(), 6);
        assert_eq!(grid.overrides(1), ["x.a=1", "x.b=20"]);
        assert_eq!(grid.overrides(2), ["x.a=2", "x.b=10"]);
        let e = a.clone().zip(b).unwrap_err().to_string();
        assert!(e.contains("3 values") && e.contains("has 2"), "{e}");
        let zipped = a.clone().zip(parse_vary("x.c=4:6:3").unwrap()).unwrap();
        assert_eq!(zipped.overrides(2), ["x.a=3", "x.c=6"]);
        assert!(a.clone().product(a).unwrap_err().to_string().contains("twice"));
        assert_eq!(Plan::from_cases_csv(&grid.to_cases_csv(), "cases.csv").unwrap(), grid);
    }

    #[test]
    fn sweep_files_keep_the_written_order_and_explicit_cases() {
        let text = r#"
config = "base.toml"
set = ["time.end = 0.5"]
[vary]
material.youngs_modulus = "1e6..1e8:3"
initial.angle_deg = [10, 20.5]
"gravity.g" = 9.81
"#;
        let f = parse_sweep_file(text, "s.toml", Some(Path::new("studies"))).unwrap();
        assert_eq!(f.config.as_deref(), Some(Path::new("studies/base.toml")));
        assert_eq!(f.set, ["time.end = 0.5"]);
        let keys: Vec<&str> = f.plans.iter().map(|p| p.keys[0].as_str()).collect();
        assert_eq!(keys, ["material.youngs_modulus", "initial.angle_deg", "gravity.g"]);
        assert_eq!(f.plans[1].cases, [[Some("10".to_string())], [Some("20.5".to_string())]]);

        let text = r#"
[[case]]
material.youngs_modulus = 1e6
[[case]]
initial.angle_deg = 45
material.model = "saint-venant-kirchhoff"
"#;
        let f = parse_sweep_file(text, "s.toml", None).unwrap();
        let p = &f.plans[0];
        assert_eq!(
            p.keys,
            ["material.youngs_modulus", "initial.angle_deg", "material.model"]
        );
        assert_eq!(p.overrides(0), ["material.youngs_modulus=1e6"]);
        assert_eq!(
            p.overrides(1),
            ["initial.angle_deg=45", "material.model=\"saint-venant-kirchhoff\""]
        );
        assert_eq!(p.shown(1)[2].1, "saint-venant-kirchhoff");
        assert_eq!(p.shown(0)[1].1, "", "a key the case leaves alone");
        assert_eq!(&Plan::from_cases_csv(&p.to_cases_csv(), "cases.csv").unwrap(), p);
        let e = parse_sweep_file("[vary]\nx.y = \"1:2\"\n", "s.toml", None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("s.toml") && e.contains("vary.x.y"), "{e}");
        let e = parse_sweep_file("cases = 1\n", "s.toml", None).unwrap_err().to_string();
        assert!(e.contains("`cases`"), "{e}");
    }
}
