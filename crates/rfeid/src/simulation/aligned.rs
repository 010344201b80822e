//! Numbers stored from a cache-line boundary.
//!
//! The dense kernels read their panels four lanes (32 bytes) at a time. A
//! heap vector of `f64` starts wherever the allocator puts it (16-byte
//! aligned), and then every other four-lane load can straddle two cache
//! lines, which costs a few percent of a small model's run depending on
//! what was allocated before. [`Aligned`] starts its numbers on a 64-byte
//! boundary.
use std::ops::Deref;

/// A fixed-length slice of `f64` whose first number sits on a 64-byte
/// boundary.
#[derive(Debug, Default)]
pub(crate) struct Aligned {
    /// Storage with room to shift the start to the boundary.
    buf: Vec<f64>,
    /// Index in `buf` of the first number.
    start: usize,
    /// Number of numbers.
    len: usize,
}

/// Numbers per cache line.
const LINE: usize = 64 / std::mem::size_of::<f64>();

impl Aligned {
    /// A copy of `values` starting on a 64-byte boundary.
    pub fn from_slice(values: &[f64]) -> Aligned {
        let mut buf = vec![0.0; values.len() + LINE - 1];
        let start = buf.as_ptr().align_offset(64).min(LINE - 1);
        buf[start..start + values.len()].copy_from_slice(values);
        Aligned {
            buf,
            start,
            len: values.len(),
        }
    }
}

impl Clone for Aligned {
    /// A copy aligned in its own storage (a cloned `Vec` may start
    /// elsewhere, and the offset with it).
    fn clone(&self) -> Aligned {
        Aligned::from_slice(self)
    }
}

impl Deref for Aligned {
    type Target = [f64];

    fn deref(&self) -> &[f64] {
        &self.buf[self.start..self.start + self.len]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The numbers are the same and start on a cache line, whatever the
    /// length.
    #[test]
    fn starts_on_a_cache_line() {
        for len in [0, 1, 7, 8, 9, 100] {
            let v: Vec<f64> = (0..len).map(|i| i as f64 + 0.5).collect();
            let a = Aligned::from_slice(&v);
            assert_eq!(&a[..], &v[..]);
            let b = a.clone();
            assert_eq!(&b[..], &v[..]);
            if len > 0 {
                assert_eq!(a.as_ptr() as usize % 64, 0, "len {len}");
                assert_eq!(b.as_ptr() as usize % 64, 0, "clone, len {len}");
            }
        }
    }
}
