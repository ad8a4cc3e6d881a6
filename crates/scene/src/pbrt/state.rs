//! The graphics state pbrt-v4 keeps while reading: the current transform
//! (each transform statement right-multiplies it), the named coordinate
//! systems, and the attributes AttributeBegin/End save and restore
//! (transform, orientation, material, area light, media, `Attribute`
//! defaults).

use super::params::{Param, ParamList};
use super::tokenizer::Loc;
use glam::{DMat4, DVec3};
use std::rc::Rc;

/// The material a shape gets: an anonymous `Material` (its index in the
/// list of materials) or a `NamedMaterial`.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialRef {
    Index(usize),
    Named(String, Loc),
}

/// What AttributeBegin pushes.
#[derive(Clone)]
pub struct Attributes {
    pub ctm: DMat4,
    pub reverse_orientation: bool,
    pub material: MaterialRef,
    /// `AreaLightSource` parameters for the shapes that follow.
    pub area_light: Option<Rc<(String, ParamList, Loc)>>,
    /// `MediumInterface "inside" "outside"` ("" is vacuum).
    pub inside: String,
    pub outside: String,
    /// `Attribute "target"` defaults: (target, parameter).
    pub defaults: Vec<(String, Param)>,
}

impl Default for Attributes {
    /// The state at the start of a file: identity, the default material
    /// (index 0, pbrt's `diffuse`), no media.
    fn default() -> Attributes {
        Attributes {
            ctm: DMat4::IDENTITY,
            reverse_orientation: false,
            material: MaterialRef::Index(0),
            area_light: None,
            inside: String::new(),
            outside: String::new(),
            defaults: Vec::new(),
        }
    }
}

/// `Translate x y z`.
pub fn translate(v: [f64; 3]) -> DMat4 {
    DMat4::from_translation(DVec3::from(v))
}

/// `Scale x y z`.
pub fn scale(v: [f64; 3]) -> DMat4 {
    DMat4::from_scale(DVec3::from(v))
}

/// `Rotate angle x y z`: degrees about the (normalised) axis; `None` for
/// a zero axis.
pub fn rotate(deg: f64, axis: [f64; 3]) -> Option<DMat4> {
    let a = DVec3::from(axis).try_normalize()?;
    Some(DMat4::from_axis_angle(a, deg.to_radians()))
}

/// `LookAt`: pbrt's camera-from-world with camera +x =
/// normalize(up × dir) (a left-handed camera frame: +x right, +y up, +z
/// forward); `None` when eye = look or up is parallel to the view.
pub fn look_at(v: &[f64; 9]) -> Option<DMat4> {
    let eye = DVec3::new(v[0], v[1], v[2]);
    let look = DVec3::new(v[3], v[4], v[5]);
    let up = DVec3::new(v[6], v[7], v[8]).try_normalize()?;
    let dir = (look - eye).try_normalize()?;
    let right = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        eye.extend(1.0),
    );
    Some(world_from_camera.inverse())
}

/// `Transform`/`ConcatTransform`: 16 numbers in column-major order (the
/// translation is elements 12–14), as glam stores a matrix.
pub fn matrix(v: &[f64; 16]) -> DMat4 {
    DMat4::from_cols_array(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_major_transform_translates_by_elements_12_to_14() {
        let mut v = [0.0; 16];
        for i in [0, 5, 10, 15] {
            v[i] = 1.0;
        }
        v[12] = 3.0;
        v[13] = 4.0;
        let p = matrix(&v).transform_point3(DVec3::ZERO);
        assert_eq!(p, DVec3::new(3.0, 4.0, 0.0));
    }

    #[test]
    fn look_at_is_left_handed() {
        // Eye on +z looking at the origin with +y up: camera +x is world −x.
        let m = look_at(&[0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]).unwrap();
        let w = m.inverse();
        let right = w.transform_vector3(DVec3::X);
        assert!((right - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
        assert!((w.transform_point3(DVec3::ZERO) - DVec3::new(0.0, 0.0, 5.0)).length() < 1e-12);
    }
}
