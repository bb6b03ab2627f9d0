//! Packing the FMUs: `modelDescription.xml` (generated from [`crate::variables::VARIABLES`]) and the
//! shared object, zipped with deflate: the FMI 2.0 FMU with `binaries/linux64/PendulumFem.so`
//! ([`write_fmu`]), the FMI 3.0 FMU with `binaries/x86_64-linux/PendulumFem3.so` ([`write_fmu3`]),
//! the same library under two names (it exports both the `fmi2*` and the `fmi3*` functions).

use std::io::Write;
use std::path::Path;

use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

use crate::variables::{model_description, model_description_fmi3, MODEL_IDENTIFIER, MODEL_IDENTIFIER_FMI3};

/// The platform folder of the shared object inside the FMI 2.0 FMU.
pub const PLATFORM: &str = "linux64";

/// The platform tuple folder of the shared object inside the FMI 3.0 FMU.
pub const PLATFORM_FMI3: &str = "x86_64-linux";

/// The name of the shared object this crate builds (`cargo build -p pendulum-fem-fmu`).
pub const LIBRARY_FILE: &str = "libpendulum_fem_fmu.so";

/// Writes the FMI 2.0 FMU archive `fmu` from the shared object `library` (the cdylib of this crate);
/// the archive is written to a temporary name first and renamed, so a reader never sees half of it.
pub fn write_fmu(library: &Path, fmu: &Path) -> std::io::Result<()> {
    let binary = format!("binaries/{PLATFORM}/{MODEL_IDENTIFIER}.so");
    pack(library, fmu, &model_description(), &binary)
}

/// Writes the FMI 3.0 FMU archive `fmu` (`PendulumFem3`) from the same shared object, as
/// [`write_fmu`] does.
pub fn write_fmu3(library: &Path, fmu: &Path) -> std::io::Result<()> {
    let binary = format!("binaries/{PLATFORM_FMI3}/{MODEL_IDENTIFIER_FMI3}.so");
    pack(library, fmu, &model_description_fmi3(), &binary)
}

/// Zips `description` and the shared object `library` (as `binary`) into `fmu`.
fn pack(library: &Path, fmu: &Path, description: &str, binary: &str) -> std::io::Result<()> {
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
        zip.write_all(description.as_bytes())?;
        zip.start_file(binary, options.unix_permissions(0o755))?;
        zip.write_all(&so)?;
        zip.finish()?;
    }
    std::fs::rename(&partial, fmu)
}
