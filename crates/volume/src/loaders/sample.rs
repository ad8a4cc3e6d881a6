//! Binary sample types of scientific volume files and their decoding in
//! either byte order.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    U64,
    I64,
    F32,
    F64,
}

impl SampleType {
    pub fn bytes(self) -> usize {
        match self {
            SampleType::U8 | SampleType::I8 => 1,
            SampleType::U16 | SampleType::I16 => 2,
            SampleType::U32 | SampleType::I32 | SampleType::F32 => 4,
            SampleType::U64 | SampleType::I64 | SampleType::F64 => 8,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SampleType::U8 => "uint8",
            SampleType::I8 => "int8",
            SampleType::U16 => "uint16",
            SampleType::I16 => "int16",
            SampleType::U32 => "uint32",
            SampleType::I32 => "int32",
            SampleType::U64 => "uint64",
            SampleType::I64 => "int64",
            SampleType::F32 => "float32",
            SampleType::F64 => "float64",
        }
    }

    /// One sample from the first `self.bytes()` bytes of `b`.
    pub fn decode(self, b: &[u8], big_endian: bool) -> f64 {
        let mut a = [0u8; 8];
        let n = self.bytes();
        a[..n].copy_from_slice(&b[..n]);
        if big_endian {
            a[..n].reverse();
        }
        match self {
            SampleType::U8 => a[0] as f64,
            SampleType::I8 => a[0] as i8 as f64,
            SampleType::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
            SampleType::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
            SampleType::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            SampleType::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            SampleType::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            SampleType::U64 => u64::from_le_bytes(a) as f64,
            SampleType::I64 => i64::from_le_bytes(a) as f64,
            SampleType::F64 => f64::from_le_bytes(a),
        }
    }
}

#[cfg(test)]
mod sample_test {
    use super::SampleType::*;

    #[test]
    fn decodes_both_byte_orders() {
        assert_eq!(I16.decode(&[0xff, 0xfe], false), -257.0);
        assert_eq!(I16.decode(&[0xfe, 0xff], true), -257.0);
        assert_eq!(I8.decode(&[0x80], false), -128.0);
        assert_eq!(U32.decode(&[0, 0, 0, 1], true), 1.0);
        assert_eq!(F32.decode(&1.5f32.to_be_bytes(), true), 1.5);
        assert_eq!(F64.decode(&(-2.25f64).to_le_bytes(), false), -2.25);
        assert_eq!(I64.decode(&(-3i64).to_be_bytes(), true), -3.0);
    }
}
