//! Parameter studies from Python (`pendulum_fem.sweep`): the CLI's `pendulum-fem sweep` cases and
//! summary rows, one case per call, so that a Python driver (a loop, a thread pool or the tasks of
//! a `dask.distributed` cluster) runs each case exactly as the CLI does.
//!
//! * [`expand`]: the cases of `--vary` arguments, `--zip` and a list of case dicts (the `[[case]]`
//!   tables of a sweep file), through [`grid::parse_vary`] and [`grid::parse_sweep_file`]: the
//!   values shown in the summary and each case's `key=value` overrides.
//! * [`run_case`]: one case (the base configuration, the overrides, the lean outputs of
//!   [`case::lean_outputs`]) through [`case::run_case`], without the GIL; its summary row as a dict.
//! * [`summary_csv`]: the rows as the text of the CLI's `summary.csv` ([`case::header`],
//!   [`case::CaseRow::csv_line`]); the rows are read back as `--gather` reads case folders.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt, PyList, PyString};

use pendulum_fem_core::{Config, Error};
use pendulum_fem_run::study::case::{self, CaseOptions, CaseRow};
use pendulum_fem_run::study::grid::{self, Plan};

/// A dotted configuration key as a TOML key (bare parts where they may be, quoted otherwise).
fn toml_key(key: &str) -> String {
    key.split('.')
        .map(|part| {
            let bare = !part.is_empty() && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            match bare {
                true => part.to_string(),
                false => toml::Value::String(part.to_string()).to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// Appends the `key = value` lines of a case dict ([`crate::dict_items`]).
fn case_lines(dict: &Bound<'_, PyDict>, out: &mut String) -> PyResult<()> {
    for (key, value) in crate::dict_items("", dict, "sweep: ")? {
        out.push_str(&format!("{} = {value}\n", toml_key(&key)));
    }
    Ok(())
}

/// The plan of a list of case dicts: the `[[case]]` tables of a sweep file with these values.
fn case_plan(cases: &Bound<'_, PyList>) -> PyResult<Plan> {
    let mut text = String::new();
    for (i, c) in cases.iter().enumerate() {
        let dict = c
            .cast::<PyDict>()
            .map_err(|_| PyValueError::new_err(format!("sweep: case {i} is not a dict of configuration keys")))?;
        text.push_str("[[case]]\n");
        case_lines(dict, &mut text)?;
    }
    let file = grid::parse_sweep_file(&text, "cases", None).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(file.plans.into_iter().next().unwrap_or_else(Plan::unit))
}

/// `expand(vary=[], zip=False, cases=None) -> dict`: the cases of a study as `pendulum-fem sweep`
/// makes them: `cases` (a list of dicts, the `[[case]]` tables of a sweep file) first, then each
/// `vary` (`KEY=VALUES`), as a grid or, with `zip`, paired. Returns `keys` (the varied keys),
/// `shown` (per case, `(key, value as in the summary)` pairs), `overrides` (per case, its
/// `key=value` overrides) and `cases_csv` (the sweep folder's `cases.csv`).
#[pyfunction]
#[pyo3(signature = (vary = Vec::new(), zip = false, cases = None))]
pub fn expand<'py>(
    py: Python<'py>,
    vary: Vec<String>,
    zip: bool,
    cases: Option<Bound<'py, PyList>>,
) -> PyResult<Bound<'py, PyDict>> {
    let bad = |e: pendulum_fem_core::Error| PyValueError::new_err(e.to_string());
    let mut plans = Vec::new();
    if let Some(c) = &cases {
        plans.push(case_plan(c)?);
    }
    for v in &vary {
        plans.push(grid::parse_vary(v).map_err(bad)?);
    }
    let mut plan = Plan::unit();
    for p in plans {
        plan = if zip { plan.zip(p) } else { plan.product(p) }.map_err(bad)?;
    }
    if plan.keys.is_empty() {
        return Err(PyValueError::new_err(format!(
            "sweep: nothing to vary; give cases (a list of dicts) or vary=[\"KEY=VALUES\"] (VALUES {})",
            grid::VALUE_FORMS
        )));
    }
    let out = PyDict::new(py);
    out.set_item("keys", plan.keys.clone())?;
    out.set_item("shown", (0..plan.len()).map(|k| plan.shown(k)).collect::<Vec<_>>())?;
    out.set_item(
        "overrides",
        (0..plan.len()).map(|k| plan.overrides(k)).collect::<Vec<_>>(),
    )?;
    out.set_item("cases_csv", plan.to_cases_csv())?;
    Ok(out)
}

/// `overrides_of(config: dict) -> list[str]`: a dict of configuration keys (nested sections or
/// dotted keys) as the CLI's `--set key=value` overrides.
#[pyfunction]
pub fn overrides_of(config: &Bound<'_, PyDict>) -> PyResult<Vec<String>> {
    let mut out = Vec::new();
    crate::flatten(config, &mut out)?;
    Ok(out)
}

/// A fresh scratch folder for a case that keeps no outputs.
fn scratch_dir() -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    std::env::temp_dir().join(format!(
        "pendulum-fem-case-{}-{}-{nanos}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::SeqCst)
    ))
}

/// The row as a dict: column name → value (`None` for an empty cell; `steps` and
/// `newton_iterations` as ints, the other metrics as floats, the varied values, `status` and
/// `message` as text); the wall columns only when the case had a wall.
fn row_dict<'py>(py: Python<'py>, row: &CaseRow) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, cell) in row.values(row.has_wall()) {
        match cell {
            case::Cell::Empty => d.set_item(name, py.None())?,
            case::Cell::Text(s) => d.set_item(name, s)?,
            case::Cell::Number(v) if name == "steps" || name == "newton_iterations" => d.set_item(name, v as u64)?,
            case::Cell::Number(v) => d.set_item(name, v)?,
        }
    }
    Ok(d)
}

/// `run_case(varied, overrides, config=None, case_dir=None, threads=1, all_outputs=False) -> dict`:
/// runs one case of a study as `pendulum-fem sweep` does: the configuration is the file `config`
/// (or the defaults) with `overrides` (`key=value`, the study's `--set` then the case's values),
/// with only `results.csv` as output unless `all_outputs` (the configuration's `[output]` switches;
/// pictures and ParaView files are the CLI's, so a case that asks for them is a failed row that says
/// so: the module carries no plotting or image code); it runs in `case_dir` (a scratch folder,
/// removed afterwards, when `None`) on a pool of `threads` threads, without the GIL. Never raises
/// for the case itself: a configuration error or a failed run is a row with `status = "failed"`
/// and the message. `varied` are the `(key, value)` pairs shown in the row.
#[pyfunction]
#[pyo3(signature = (varied, overrides, config = None, case_dir = None, threads = 1, all_outputs = false))]
pub fn run_case<'py>(
    py: Python<'py>,
    varied: Vec<(String, String)>,
    overrides: Vec<String>,
    config: Option<PathBuf>,
    case_dir: Option<PathBuf>,
    threads: usize,
    all_outputs: bool,
) -> PyResult<Bound<'py, PyDict>> {
    if threads == 0 {
        return Err(PyValueError::new_err("run_case: threads must be >= 1"));
    }
    let row = py.detach(|| {
        let cfg = Config::load(config.as_deref(), &overrides).map(|mut c| {
            if !all_outputs {
                case::lean_outputs(&mut c);
            }
            c
        });
        // the pictures are drawn by the CLI (`pendulum-fem-render`), which this module leaves out
        let cfg =
            cfg.and_then(
                |c| match c.output.plots || c.output.animation || c.output.paraview || c.output.viewer {
                    true => Err(Error::Input(
                        "all_outputs: this configuration asks for plots, animations, ParaView frames or the viewer \
                 ([output] plots, animation, paraview, viewer), which the Python package does not draw: set them \
                 to false, or run the study with `pendulum-fem sweep --all-outputs`"
                            .into(),
                    )),
                    false => Ok(c),
                },
            );
        let opts = CaseOptions {
            threads,
            stop: None,
            observers: Vec::new(),
        };
        match &case_dir {
            Some(dir) => case::run_case(varied, cfg, dir, &opts),
            None => {
                let dir = scratch_dir();
                let row = case::run_case(varied, cfg, &dir, &opts);
                let _ = std::fs::remove_dir_all(&dir);
                row
            }
        }
    });
    row_dict(py, &row)
}

/// One cell of a row dict as CSV text (numbers in the summary's round-trip form).
fn cell_text(name: &str, v: &Bound<'_, PyAny>) -> PyResult<String> {
    if v.is_none() {
        Ok(String::new())
    } else if v.is_instance_of::<PyString>() {
        Ok(case::csv_field(&v.extract::<String>()?))
    } else if v.is_instance_of::<PyInt>() {
        Ok(v.extract::<i64>()?.to_string())
    } else if v.is_instance_of::<PyFloat>() {
        Ok(case::number_text(v.extract()?))
    } else {
        Err(PyValueError::new_err(format!(
            "summary_csv: column `{name}` holds a {}, not a number, a string or None",
            v.get_type().name()?
        )))
    }
}

/// `summary_csv(keys, rows) -> str`: the text of the CLI's `summary.csv` for the varied `keys`
/// and the row dicts of [`run_case`], in case order (the wall columns when any case had a wall).
#[pyfunction]
pub fn summary_csv(keys: Vec<String>, rows: Vec<Bound<'_, PyDict>>) -> PyResult<String> {
    let mut parsed = Vec::with_capacity(rows.len());
    for (k, d) in rows.iter().enumerate() {
        let mut names = Vec::new();
        let mut cells = Vec::new();
        for (name, v) in d.iter() {
            let name: String = name.extract()?;
            cells.push(cell_text(&name, &v)?);
            names.push(case::csv_field(&name));
        }
        let row = CaseRow::parse(&names.join(","), &cells.join(","))
            .map_err(|m| PyValueError::new_err(format!("summary_csv: row {k}: {m}")))?;
        let varied: Vec<&String> = row.varied.iter().map(|(key, _)| key).collect();
        if varied != keys.iter().collect::<Vec<_>>() {
            return Err(PyValueError::new_err(format!(
                "summary_csv: row {k} has the varied keys {varied:?}, the study {keys:?}"
            )));
        }
        parsed.push(row);
    }
    let wall = parsed.iter().any(CaseRow::has_wall);
    let mut text = case::header(&keys, wall);
    text.push('\n');
    for row in &parsed {
        text.push_str(&row.csv_line(wall));
        text.push('\n');
    }
    Ok(text)
}

/// Adds the study functions to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(expand, m)?)?;
    m.add_function(wrap_pyfunction!(overrides_of, m)?)?;
    m.add_function(wrap_pyfunction!(run_case, m)?)?;
    m.add_function(wrap_pyfunction!(summary_csv, m)?)?;
    Ok(())
}
