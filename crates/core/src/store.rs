//! The bottom layer: what every other module may use and that uses none of them but the error
//! type. Little-endian bytes with a bounds-checked reader ([`bytes`]), the FNV-1a hash of
//! checksums, fingerprints and cache keys ([`hash`]), files written whole or not at all and the
//! cache folder ([`files`]), and the one reader of numeric CSV tables ([`table`]).

pub mod bytes;
pub mod files;
pub mod hash;
pub mod table;

pub use files::{cache_folder, write_atomically, write_bytes_atomically};
pub use hash::{fnv1a, Fnv};
pub use table::Table;
