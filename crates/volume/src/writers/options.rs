//! The choices both writers share: how data is compressed, and how
//! NanoVDB stores values.

/// How a file's data is compressed: OpenVDB compresses each node buffer,
/// NanoVDB each grid buffer, with zlib (Zip) or Blosc (LZ4 frames).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Codec {
    #[default]
    None,
    Zip,
    Blosc,
}

impl Codec {
    pub fn name(self) -> &'static str {
        match self {
            Codec::None => "none",
            Codec::Zip => "zip",
            Codec::Blosc => "blosc",
        }
    }

    /// `none`, `zip` or `blosc`.
    pub fn parse(s: &str) -> Option<Codec> {
        match s {
            "none" => Some(Codec::None),
            "zip" => Some(Codec::Zip),
            "blosc" => Some(Codec::Blosc),
            _ => None,
        }
    }
}

/// How a grid's values are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NanoValue {
    /// Full-precision `float` leaves.
    #[default]
    Float,
    /// 8-bit codes per leaf (`Fp8`): error at most half of `(max − min) / 255`.
    Fp8,
    /// 16-bit codes per leaf (`Fp16`): error at most half of `(max − min) / 65535`.
    Fp16,
}

impl NanoValue {
    /// `float`, `fp8` or `fp16`.
    pub fn parse(s: &str) -> Option<NanoValue> {
        match s {
            "float" => Some(NanoValue::Float),
            "fp8" => Some(NanoValue::Fp8),
            "fp16" => Some(NanoValue::Fp16),
            _ => None,
        }
    }
}
