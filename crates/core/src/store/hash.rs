//! 64-bit FNV-1a: the checksum of every file format of the project (snapshots, cache files, FMU
//! states) and the hash of fingerprints, cache keys and the FMU's GUID. Not a cryptographic hash:
//! it detects damaged or foreign bytes and tells apart inputs that differ, nothing more.

/// 64-bit FNV-1a over a byte stream written in pieces.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(pub u64);

impl Fnv {
    /// The offset basis, the hash of no bytes.
    pub const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    /// The 64-bit FNV prime.
    pub const PRIME: u64 = 0x0000_0100_0000_01b3;

    /// The hash of no bytes.
    pub fn new() -> Self {
        Self(Self::OFFSET)
    }

    /// Continues the hash over `bytes`.
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Self::new()
    }
}

/// FNV-1a of `bytes`.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    fnv1a_from(bytes, Fnv::OFFSET)
}

/// FNV-1a of `bytes` continued from the hash `seed` (the offset basis starts a fresh hash).
pub fn fnv1a_from(bytes: &[u8], seed: u64) -> u64 {
    let mut h = Fnv(seed);
    h.write(bytes);
    h.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hash_is_the_published_fnv1a_of_its_test_vectors() {
        // test vectors of the FNV reference (Fowler, Noll, Vo): "", "a", "foobar"
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
        assert_eq!(fnv1a_from(b"bar", fnv1a(b"foo")), fnv1a(b"foobar"));
    }
}
