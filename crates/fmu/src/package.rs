//! Packing the FMU: `modelDescription.xml` (generated from [`crate::variables::VARIABLES`]) and the
//! shared object as `binaries/linux64/PendulumFem.so`, zipped with deflate.

use std::io::Write;
use std::path::Path;

use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

use crate::variables::{model_description, MODEL_IDENTIFIER};

/// The platform folder of the shared object inside the FMU.
pub const PLATFORM: &str = "linux64";

/// The name of the shared object this crate builds (`cargo build -p pendulum-fem-fmu`).
pub const LIBRARY_FILE: &str = "libpendulum_fem_fmu.so";

/// Writes the FMU archive `fmu` from the shared object `library` (the cdylib of this crate); the
/// archive is written to a temporary name first and renamed, so a reader never sees half of it.
pub fn write_fmu(library: &Path, fmu: &Path) -> std::io::Result<()> {
    let so =
        std::fs::read(library).map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", library.display())))?;
    if let Some(dir) = fmu.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let partial = fmu.with_extension("fmu.partial");
    {
        let file = std::fs::File::create(&partial)?;
        let mut zip = zip::ZipWriter::new(file);
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Deflated)
            .unix_permissions(0o644);
        zip.start_file("modelDescription.xml", options)?;
        zip.write_all(model_description().as_bytes())?;
        zip.start_file(
            format!("binaries/{PLATFORM}/{MODEL_IDENTIFIER}.so"),
            options.unix_permissions(0o755),
        )?;
        zip.write_all(&so)?;
        zip.finish()?;
    }
    std::fs::rename(&partial, fmu)
}
