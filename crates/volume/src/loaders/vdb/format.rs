//! The OpenVDB file format's constants, shared by the reader and the
//! writer (`crate::writers::vdb`): the magic number, the tree type names,
//! the per-grid compression flags (`io/Compression.h`) and the per-node
//! indicators of how inactive values are stored.

/// The first eight bytes of a `.vdb` file: the magic number 0x56444220
/// ("\x20BDV") as a little-endian i64.
pub(crate) const MAGIC: [u8; 8] = [0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0];
/// Appended to a tree type name when its values are stored as half floats.
pub(crate) const HALF_SUFFIX: &str = "_HalfFloat";
/// Separates a duplicated grid name from its index in unique names.
pub(crate) const NAME_SEP: char = '\x1e';

/// Tree type names of the grids read and written (5-4-3 trees of `float`
/// and of `vec3s` values).
pub(crate) const FLOAT_TREE: &str = "Tree_float_5_4_3";
pub(crate) const VEC3S_TREE: &str = "Tree_vec3s_5_4_3";

/// Per-grid compression flags.
pub(crate) const COMPRESS_ZIP: u32 = 0x1;
pub(crate) const COMPRESS_ACTIVE_MASK: u32 = 0x2;
pub(crate) const COMPRESS_BLOSC: u32 = 0x4;

/// Per-node indicator of how inactive values were stored, in file order:
/// none stored (all the background), all its negation, one value, a
/// selection mask with none, one or two inactive values, or every value.
pub(crate) const NO_MASK_OR_INACTIVE_VALS: u8 = 0;
pub(crate) const NO_MASK_AND_MINUS_BG: u8 = 1;
pub(crate) const NO_MASK_AND_ONE_INACTIVE_VAL: u8 = 2;
pub(crate) const MASK_AND_NO_INACTIVE_VALS: u8 = 3;
pub(crate) const MASK_AND_ONE_INACTIVE_VAL: u8 = 4;
pub(crate) const MASK_AND_TWO_INACTIVE_VALS: u8 = 5;
pub(crate) const NO_MASK_AND_ALL_VALS: u8 = 6;
