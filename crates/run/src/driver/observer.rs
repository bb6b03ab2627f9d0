//! What watches a run beside its CSV files: a [`RunObserver`], made once the simulation is set up
//! from a [`RunStart`] by the makers of [`super::RunOptions::observers`].

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pendulum_fem_core::simulation::{Simulation, StepRecord};
use pendulum_fem_core::{Config, Error};

/// What a run's observers are made from, once its simulation is set up (and, for a restart,
/// returned to its checkpoint).
pub struct RunStart<'a> {
    /// The configuration of the run.
    pub config: &'a Config,
    /// The simulation, at its first record's state.
    pub sim: &'a Simulation,
    /// The run's folder.
    pub out_dir: &'a Path,
    /// A restarted run: the `(step, time)` of every `results.csv` row up to and including the
    /// checkpoint's; empty for a fresh run.
    pub resumed: &'a [(usize, f64)],
    /// A restarted run: the records its folder holds from before the checkpoint, the rows of
    /// `results.csv` before the checkpoint's and those of `impacts.csv`, in time order (what
    /// [`RunObserver::record`] and [`RunObserver::substeps`] took before the run was stopped);
    /// empty for a fresh run.
    pub earlier: &'a [StepRecord],
}

/// Something that watches a run beside its CSV files: the pictures and ParaView frames
/// (`pendulum-fem-render`), the CLI's progress bar. The driver calls it in this order:
/// [`RunObserver::record`] for every record (the rows of `results.csv`), after each step's
/// [`RunObserver::substeps`] (the rows it adds to `impacts.csv`), [`RunObserver::sync`] before each
/// checkpoint, and [`RunObserver::finish`] once at the end, whether the run completed, was
/// interrupted or failed. The records so come in time order.
pub trait RunObserver {
    /// Takes the record of the latest step (step 0's first). `resumed`: the record is a restarted
    /// run's checkpoint, whose outputs its folder already holds.
    fn record(&mut self, sim: &mut Simulation, record: &StepRecord, resumed: bool) -> Result<(), Error>;

    /// Takes the records of the sub-steps inside an impact that the step just taken wrote to
    /// `impacts.csv` ([`Simulation::record_impacts`]), before that step's [`RunObserver::record`].
    fn substeps(&mut self, records: &[StepRecord]) -> Result<(), Error> {
        let _ = records;
        Ok(())
    }

    /// Everything observed so far is on disk (a checkpoint follows).
    fn sync(&mut self) -> Result<(), Error> {
        Ok(())
    }

    /// The run has ended at `last` (the last state computed; a record never taken when the run
    /// ended on a NaN or an infinity in it, [`StepRecord::first_non_finite`]); returns the files
    /// written.
    fn finish(self: Box<Self>, sim: &mut Simulation, last: &StepRecord) -> Result<Vec<PathBuf>, Error>;
}

/// Makes an observer for a run ([`super::RunOptions::observers`]); `None`: this run needs none (say,
/// pictures that the configuration switched off).
pub type MakeObserver = dyn Fn(&RunStart<'_>) -> Result<Option<Box<dyn RunObserver>>, Error> + Send + Sync;

/// An observer maker that [`super::RunOptions`] can hold (and clone, and print).
#[derive(Clone)]
pub struct Attach(pub Arc<MakeObserver>);

impl Attach {
    /// Wraps an observer maker.
    pub fn new(
        make: impl Fn(&RunStart<'_>) -> Result<Option<Box<dyn RunObserver>>, Error> + Send + Sync + 'static,
    ) -> Self {
        Self(Arc::new(make))
    }
}

impl std::fmt::Debug for Attach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Attach(..)")
    }
}
