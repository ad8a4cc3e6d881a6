//! NIfTI-1/2 (`nifti = "f.nii.gz"`, `.nii`, `.hdr`): `channel` picks the
//! 3D volume of a 4D file (0); placed by the sform/qform in RAS millimetres;
//! values rescaled from their range onto [0, 1].

use super::format::{Described, FieldData, FileSource, Footprint, VolumeFormat, VolumeQuery};
use super::scientific;
use crate::loaders::nifti;
use crate::Precision;

pub const FORMAT: VolumeFormat = VolumeFormat {
    key: "nifti",
    name: "NIfTI",
    extensions: &[".nii", ".nii.gz", ".hdr"],
    by_extension: true,
    read,
    describe,
    sparse: None,
    write: None,
};

fn read(s: &FileSource, precision: Precision) -> crate::Result<FieldData> {
    scientific::read(s, precision, nifti::read)
}

fn describe(out: &mut String, a: &VolumeQuery, footprint: Footprint) -> Described {
    scientific::describe(out, &a.file, footprint, nifti::read)
}
