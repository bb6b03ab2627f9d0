//! `summary_<key>.png`: every metric of the completed cases against each varied key whose values
//! are numbers, one series per combination of the other keys' values
//! ([`crate::render::summary_plot`]).

use std::path::{Path, PathBuf};

use super::case::{CaseRow, CaseStatus, Cell, METRICS, WALL_METRICS};
use crate::render::summary_plot::{write_summary_png, Panel};
use crate::Error;

/// Draws the figures; returns the files written (none for a key with text values or a single
/// value, or when no case completed).
pub fn write_plots(out: &Path, keys: &[String], rows: &[CaseRow]) -> Result<Vec<PathBuf>, Error> {
    let ok: Vec<&CaseRow> = rows.iter().filter(|r| r.status == CaseStatus::Ok).collect();
    let wall = ok.iter().any(|r| r.has_wall());
    // the final time is the same for every completed case
    let metrics: Vec<&str> = METRICS[1..]
        .iter()
        .chain(if wall { &WALL_METRICS[..] } else { &[] })
        .copied()
        .collect();
    let mut files = Vec::new();
    for (j, key) in keys.iter().enumerate() {
        let xs: Option<Vec<f64>> = ok.iter().map(|r| r.varied[j].1.parse::<f64>().ok()).collect();
        let Some(xs) = xs else { continue };
        if xs.iter().all(|x| *x == xs[0]) {
            continue;
        }
        let label = |r: &CaseRow| {
            let others: Vec<String> = r
                .varied
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != j)
                .map(|(_, (k, v))| format!("{} = {v}", k.rsplit('.').next().unwrap_or(k)))
                .collect();
            others.join(", ")
        };
        let panels: Vec<Panel> = metrics
            .iter()
            .map(|metric| {
                let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
                for (r, &x) in ok.iter().zip(&xs) {
                    let values = r.values(wall);
                    let Some((_, Cell::Number(y))) = values.iter().find(|(n, _)| n == metric) else {
                        continue;
                    };
                    let l = label(r);
                    match series.iter_mut().find(|(name, _)| *name == l) {
                        Some((_, pts)) => pts.push((x, *y)),
                        None => series.push((l, vec![(x, *y)])),
                    }
                }
                Panel {
                    metric: metric.to_string(),
                    series,
                }
            })
            .collect();
        let name: String = key
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' })
            .collect();
        let path = out.join(format!("summary_{name}.png"));
        write_summary_png(&path, key, &panels)?;
        files.push(path);
    }
    Ok(files)
}
