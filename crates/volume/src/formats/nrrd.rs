//! NRRD (`nrrd = "f.nrrd"` or `"f.nhdr"`): `channel` picks the entry of a
//! non-spatial axis (0); placed by `space directions`/`space origin`, LPS
//! turned to RAS; values rescaled onto [0, 1].

use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery};
use super::scientific;
use crate::loaders::nrrd;
use crate::Precision;

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "nrrd",
    name: "NRRD",
    extensions: &[".nrrd", ".nhdr"],
    by_extension: true,
    read,
    describe,
    sparse: None,
    write: None,
};

fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    scientific::read(s, precision, nrrd::read)
}

fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    scientific::describe(out, &a.file, footprint, nrrd::read)
}
