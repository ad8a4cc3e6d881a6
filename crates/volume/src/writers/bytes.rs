//! Little-endian appends to a byte buffer, the one way both writers emit
//! numbers (both formats are little-endian).

pub(crate) trait Put {
    fn u8(&mut self, v: u8);
    fn u32(&mut self, v: u32);
    fn i32(&mut self, v: i32);
    fn u64(&mut self, v: u64);
    fn i64(&mut self, v: i64);
    fn f32(&mut self, v: f32);
    fn f64(&mut self, v: f64);
    /// A `u32`-length-prefixed string (OpenVDB's names and metadata).
    fn string(&mut self, s: &str);
    fn mask(&mut self, words: &[u64]);
}

impl Put for Vec<u8> {
    fn u8(&mut self, v: u8) {
        self.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.extend_from_slice(&v.to_le_bytes());
    }
    fn i32(&mut self, v: i32) {
        self.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.extend_from_slice(&v.to_le_bytes());
    }
    fn i64(&mut self, v: i64) {
        self.extend_from_slice(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.extend_from_slice(&v.to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.extend_from_slice(&v.to_le_bytes());
    }
    fn string(&mut self, s: &str) {
        self.u32(s.len() as u32);
        self.extend_from_slice(s.as_bytes());
    }
    fn mask(&mut self, words: &[u64]) {
        for &w in words {
            self.u64(w);
        }
    }
}

/// Writes `v` at `at` of `buf` (which holds at least `at + N` bytes).
pub(crate) fn put_at<const N: usize>(buf: &mut [u8], at: usize, v: [u8; N]) {
    buf[at..at + N].copy_from_slice(&v);
}
