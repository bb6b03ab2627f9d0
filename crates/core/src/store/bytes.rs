//! Little-endian bytes: the writer and the bounds-checked reader of every binary format of the
//! project (snapshots, the reduced body's and the mesh's cache files). The reader never reads past
//! the end and never allocates for a count that the remaining bytes cannot hold; its errors name
//! the source, the item and the byte.

use crate::error::Error;

/// A little-endian byte writer (snapshots, the cache files).
pub struct Writer(pub Vec<u8>);

impl Writer {
    /// One byte.
    pub fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    /// A `u32`, little-endian.
    pub fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    /// A `u64`, little-endian.
    pub fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    /// A count or index as a `u64`.
    pub fn usize(&mut self, x: usize) {
        self.u64(x as u64);
    }
    /// An `f64` as its IEEE bits.
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    /// An option as a flag byte 0/1 and the value.
    pub fn opt_f64(&mut self, x: Option<f64>) {
        match x {
            Some(v) => {
                self.u8(1);
                self.f64(v);
            }
            None => self.u8(0),
        }
    }
    /// A vector as its length and its values.
    pub fn vec(&mut self, v: &[f64]) {
        self.usize(v.len());
        if cfg!(target_endian = "little") {
            // the values' bits are already their little-endian bytes
            self.0.extend_from_slice(bytemuck::cast_slice(v));
        } else {
            v.iter().for_each(|&x| self.f64(x));
        }
    }
}

/// The bounds-checked reader of [`Writer`]'s bytes; `source` names them in errors.
pub struct Reader<'a> {
    /// The bytes.
    pub bytes: &'a [u8],
    /// The position of the next byte.
    pub pos: usize,
    /// What the bytes are (a file's path), for errors.
    pub source: &'a str,
}

impl Reader<'_> {
    /// The next `n` bytes; `what` names them in the error when fewer remain.
    pub fn take(&mut self, n: usize, what: &str) -> Result<&[u8], Error> {
        if self.bytes.len() - self.pos < n {
            return Err(Error::Input(format!(
                "{}: truncated: {what} at byte {} needs {n} bytes, {} remain",
                self.source,
                self.pos,
                self.bytes.len() - self.pos
            )));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    /// One byte.
    pub fn u8(&mut self, what: &str) -> Result<u8, Error> {
        Ok(self.take(1, what)?[0])
    }
    /// A little-endian `u32`.
    pub fn u32(&mut self, what: &str) -> Result<u32, Error> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().expect("4 bytes")))
    }
    /// A little-endian `u64`.
    pub fn u64(&mut self, what: &str) -> Result<u64, Error> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().expect("8 bytes")))
    }
    /// A `u64` that fits a `usize`.
    pub fn usize(&mut self, what: &str) -> Result<usize, Error> {
        let at = self.pos;
        let x = self.u64(what)?;
        usize::try_from(x).map_err(|_| Error::Input(format!("{}: {what} at byte {at}: {x} is too large", self.source)))
    }
    /// An `f64` from its IEEE bits.
    pub fn f64(&mut self, what: &str) -> Result<f64, Error> {
        Ok(f64::from_bits(self.u64(what)?))
    }
    /// A flag byte, 0 or 1.
    pub fn flag(&mut self, what: &str) -> Result<bool, Error> {
        let at = self.pos;
        match self.u8(what)? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(Error::Input(format!(
                "{}: {what} at byte {at}: option flag {b}, allowed 0 or 1",
                self.source
            ))),
        }
    }
    /// An option written by [`Writer::opt_f64`].
    pub fn opt_f64(&mut self, what: &str) -> Result<Option<f64>, Error> {
        Ok(if self.flag(what)? { Some(self.f64(what)?) } else { None })
    }
    /// A count of items of `size` bytes each, checked against the bytes left before anything is
    /// allocated for them.
    pub fn count(&mut self, what: &str, size: usize) -> Result<usize, Error> {
        let n = self.usize(what)?;
        if n > (self.bytes.len() - self.pos) / size.max(1) {
            return Err(Error::Input(format!(
                "{}: truncated: {what} of {n} values at byte {}",
                self.source, self.pos
            )));
        }
        Ok(n)
    }
    /// A vector written by [`Writer::vec`].
    pub fn vec(&mut self, what: &str) -> Result<Vec<f64>, Error> {
        let n = self.count(what, 8)?;
        let bytes = self.take(8 * n, what)?;
        Ok(bytes
            .chunks_exact(8)
            .map(|b| f64::from_bits(u64::from_le_bytes(b.try_into().expect("8 bytes"))))
            .collect())
    }
}
