//! Grid value types and the byte layout of the root, internal nodes and
//! leaves they imply. NanoVDB's node structs are plain C++ structs, each
//! 32-byte aligned, whose fields follow C layout rules: a field starts at
//! the next multiple of its alignment, the node's table or voxel array at
//! the next multiple of 32. The offsets below follow from the value type's
//! size and alignment and from its statistics type (`float` for values of
//! 4-byte elements, `double` for 8-byte ones).

/// The grid types the reader reads (`GridType` numbers 1, 2, 6, 7, 13–16).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ValueKind {
    Float,
    Double,
    Vec3f,
    Vec3d,
    Fp4,
    Fp8,
    Fp16,
    FpN,
}

/// NanoVDB's name for `GridType` `t`, as `nanovdb_print` shows it.
pub(crate) fn type_name(t: u32) -> &'static str {
    const NAMES: [&str; 27] = [
        "unknown",
        "float",
        "double",
        "int16",
        "int32",
        "int64",
        "Vec3f",
        "Vec3d",
        "Mask",
        "Half",
        "uint32",
        "bool",
        "RGBA8",
        "Fp4",
        "Fp8",
        "Fp16",
        "FpN",
        "Vec4f",
        "Vec4d",
        "Index",
        "OnIndex",
        "IndexMask",
        "OnIndexMask",
        "PointIndex",
        "Vec3u8",
        "Vec3u16",
        "UInt8",
    ];
    NAMES.get(t as usize).copied().unwrap_or("unknown")
}

impl ValueKind {
    pub(crate) fn from_grid_type(t: u32) -> Option<ValueKind> {
        Some(match t {
            1 => ValueKind::Float,
            2 => ValueKind::Double,
            6 => ValueKind::Vec3f,
            7 => ValueKind::Vec3d,
            13 => ValueKind::Fp4,
            14 => ValueKind::Fp8,
            15 => ValueKind::Fp16,
            16 => ValueKind::FpN,
            _ => return None,
        })
    }

    /// Floats per value.
    pub(crate) fn components(self) -> usize {
        match self {
            ValueKind::Vec3f | ValueKind::Vec3d => 3,
            _ => 1,
        }
    }

    /// Bytes per component of the root's and internal nodes' values
    /// (quantised grids keep those as `float`).
    pub(crate) fn element_size(self) -> usize {
        match self {
            ValueKind::Double | ValueKind::Vec3d => 8,
            _ => 4,
        }
    }

    /// Code width of fixed-width quantised leaves.
    pub(crate) fn code_bits(self) -> Option<u32> {
        match self {
            ValueKind::Fp4 => Some(4),
            ValueKind::Fp8 => Some(8),
            ValueKind::Fp16 => Some(16),
            _ => None,
        }
    }

    pub(crate) fn is_quantised(self) -> bool {
        matches!(
            self,
            ValueKind::Fp4 | ValueKind::Fp8 | ValueKind::Fp16 | ValueKind::FpN
        )
    }
}

fn align(x: usize, a: usize) -> usize {
    x.div_ceil(a) * a
}

/// An internal node: 32³ (upper, log2 dimension 5) or 16³ (lower, 4).
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeLayout {
    pub(crate) log2: u32,
    /// log2 of the child's edge length in voxels: 7 below an upper node,
    /// 3 below a lower one.
    pub(crate) child_total: u32,
    pub(crate) value_mask: usize,
    pub(crate) child_mask: usize,
    pub(crate) table: usize,
    /// Bytes per table entry: the value, or an `i64` child offset.
    pub(crate) entry: usize,
    pub(crate) size: usize,
}

/// Byte layout of a grid's nodes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Layout {
    pub(crate) kind: ValueKind,
    /// Root: background value offset and size of `RootData`.
    pub(crate) root_background: usize,
    pub(crate) root_size: usize,
    /// Root tile: value offset and tile size (key `u64`, child `i64` and
    /// state `u32` come first).
    pub(crate) tile_value: usize,
    pub(crate) tile_size: usize,
    pub(crate) upper: NodeLayout,
    pub(crate) lower: NodeLayout,
    /// Leaf: where its value array starts and its size; quantised leaves
    /// start their codes at 96, FpN leaves vary in size.
    pub(crate) leaf_values: usize,
    pub(crate) leaf_size: usize,
}

/// The leaf header: origin (3 × i32), bbox extent (3 × u8), flags (u8) and
/// the 64-byte value mask.
pub(crate) const LEAF_MASK: usize = 16;
pub(crate) const LEAF_HEADER: usize = 80;
/// Quantised leaves: minimum and quantum (f32), four u16 statistics, then
/// the codes.
pub(crate) const FP_MINIMUM: usize = 80;
pub(crate) const FP_QUANTUM: usize = 84;
pub(crate) const FP_CODES: usize = 96;

impl Layout {
    pub(crate) fn new(kind: ValueKind) -> Layout {
        let elem = kind.element_size();
        // Quantised leaves hold floats; their nodes' values are floats.
        let value = elem * kind.components();
        let stats = elem;
        // `values` values (the root adds the background to minimum and
        // maximum) from `start`, then average and standard deviation.
        let fields = |start: usize, values: usize| {
            let first = align(start, elem);
            align(first + values * value, stats) + 2 * stats
        };
        let node = |log2: u32, child_total: u32| {
            let mask = (1usize << (3 * log2)) / 8;
            let table = align(fields(32 + 2 * mask, 2), 32);
            let entry = align(value.max(8), elem.max(8));
            NodeLayout {
                log2,
                child_total,
                value_mask: 32,
                child_mask: 32 + mask,
                table,
                entry,
                size: align(table + (1usize << (3 * log2)) * entry, 32),
            }
        };
        let leaf_values = if kind.is_quantised() {
            FP_CODES
        } else {
            align(fields(LEAF_HEADER, 2), 32)
        };
        let leaf_size = match kind.code_bits() {
            Some(bits) => FP_CODES + 512 * bits as usize / 8,
            None if kind == ValueKind::FpN => FP_CODES,
            None => align(leaf_values + 512 * value, 32),
        };
        Layout {
            kind,
            root_background: align(28, elem),
            root_size: align(fields(28, 3), 32),
            tile_value: align(20, elem),
            tile_size: align(align(20, elem) + value, 32),
            upper: node(5, 7),
            lower: node(4, 3),
            leaf_values,
            leaf_size,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sizes NanoVDB documents for float grids (`NanoVDB.h`: upper 270,400
    /// B, lower 33,856 B, leaf 2,144 B, root 64 B, root tile 32 B).
    #[test]
    fn float_layout_matches_nanovdb_sizes() {
        let l = Layout::new(ValueKind::Float);
        assert_eq!(l.upper.size, 270_400);
        assert_eq!(l.lower.size, 33_856);
        assert_eq!((l.leaf_values, l.leaf_size), (96, 2144));
        assert_eq!((l.root_background, l.root_size), (28, 64));
        assert_eq!((l.tile_value, l.tile_size), (20, 32));
        let v = Layout::new(ValueKind::Vec3f);
        assert_eq!((v.root_size, v.tile_size, v.leaf_values), (96, 32, 128));
        let fp8 = Layout::new(ValueKind::Fp8);
        assert_eq!((fp8.leaf_size, fp8.upper.size), (96 + 512, 270_400));
    }
}
