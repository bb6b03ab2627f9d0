//! Parameter studies: the grid of cases ([`grid`]: `--vary` values, ranges, zipped keys, sweep
//! files) and one case run with its summary row ([`case`]). The `sweep` command of the CLI and the
//! Python package's `sweep` (local or on a Dask cluster) both use these, so a case gives the same
//! row whichever runs it.

pub mod case;
pub mod grid;
