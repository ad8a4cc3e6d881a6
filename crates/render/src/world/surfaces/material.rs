//! What the integrators evaluate at a hit point: a shape's material (one
//! side, or Mitsuba's `twosided`), built from its `bsdf` table
//! ([`BsdfDesc`], the TOML schema), with its textures looked up at the hit's
//! UV.

use super::bsdf_desc::distribution_of;
pub use super::bsdf_desc::BsdfDesc;
use super::ior::IorDesc;
pub use super::spectrum::{SpectrumDesc, TextureDesc, UvTransformDesc};
use crate::error::SceneError;
use crate::world::bitmap::BitmapFiles;
use crate::world::bsdf::{Bsdf, BsdfSample, Microfacet, Plastic, RoughPlastic, TwoSided};
use crate::world::texture::Texture;
use glam::{Vec2, Vec3};
use std::path::Path;

/// One side's BSDF and the texture that replaces its reflectance (diffuse
/// reflectance, plastic base, conductor tint) at each hit.
#[derive(Clone, Debug, PartialEq)]
pub struct Side {
    pub bsdf: Bsdf,
    pub texture: Option<Texture>,
}

impl Side {
    fn at(&self, uv: Vec2) -> Bsdf {
        let Some(t) = &self.texture else {
            return self.bsdf;
        };
        let c = t.eval(uv);
        match self.bsdf {
            Bsdf::Diffuse { .. } => Bsdf::Diffuse { reflectance: c },
            Bsdf::Plastic(p) => Bsdf::Plastic(Plastic { diffuse: c, ..p }),
            Bsdf::RoughPlastic(p) => Bsdf::RoughPlastic(p.with_diffuse(c)),
            Bsdf::Conductor { eta, k, mf, .. } => Bsdf::Conductor {
                eta,
                k,
                mf,
                specular: c,
            },
            b => b,
        }
    }
}

/// A shape's material: one side, or Mitsuba's `twosided` (the back side
/// seen in the mirrored frame).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub front: Side,
    pub back: Option<Side>,
}

/// The BSDF at one hit point, in the shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceBsdf {
    One(Bsdf),
    Two(TwoSided),
}

impl SurfaceBsdf {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            SurfaceBsdf::One(b) => b.eval(wo, wi),
            SurfaceBsdf::Two(b) => b.eval(wo, wi),
        }
    }
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            SurfaceBsdf::One(b) => b.pdf(wo, wi),
            SurfaceBsdf::Two(b) => b.pdf(wo, wi),
        }
    }
    pub fn sample(&self, wo: Vec3, uc: f32, u: [f32; 2]) -> Option<BsdfSample> {
        match self {
            SurfaceBsdf::One(b) => b.sample(wo, uc, u),
            SurfaceBsdf::Two(b) => b.sample(wo, uc, u),
        }
    }
    /// Whether light sampling cannot help (every lobe of both sides is a delta).
    pub fn is_delta(&self) -> bool {
        match self {
            SurfaceBsdf::One(b) => b.is_delta(),
            SurfaceBsdf::Two(b) => b.front.is_delta() && b.back.is_delta(),
        }
    }
}

impl Material {
    pub fn is_null(&self) -> bool {
        self.front.bsdf == Bsdf::Null && self.back.is_none()
    }

    /// Whether a side has a delta lobe ([`Bsdf::has_delta_lobe`]).
    pub fn has_delta_lobe(&self) -> bool {
        self.front.bsdf.has_delta_lobe()
            || self.back.as_ref().is_some_and(|b| b.bsdf.has_delta_lobe())
    }

    /// Whether some light passes straight through (null, thin dielectric).
    pub fn passes_light(&self) -> bool {
        self.front.bsdf.null_transmission(1.0).is_some()
            && self
                .back
                .as_ref()
                .is_none_or(|b| b.bsdf.null_transmission(1.0).is_some())
    }

    /// The fraction of light passing straight through at cosine `cos` with
    /// the shading normal (the side's [`Bsdf::null_transmission`]).
    pub fn null_transmission(&self, cos: f32) -> Option<f32> {
        match &self.back {
            Some(b) if cos < 0.0 => b.bsdf.null_transmission(cos),
            _ => self.front.bsdf.null_transmission(cos),
        }
    }

    /// The BSDF at a hit with texture coordinates `uv`.
    pub fn at(&self, uv: Vec2) -> SurfaceBsdf {
        match &self.back {
            None => SurfaceBsdf::One(self.front.at(uv)),
            Some(back) => SurfaceBsdf::Two(TwoSided {
                front: self.front.at(uv),
                back: back.at(uv),
            }),
        }
    }
}

impl BsdfDesc {
    /// The material; `key` names the table in messages (`shapes.2.bsdf`),
    /// `base` is the folder that texture files are relative to.
    pub fn build(&self, key: &str, base: &Path) -> Result<Material, SceneError> {
        self.build_with(key, &BitmapFiles::new(base))
    }

    /// [`BsdfDesc::build`] reading texture files through `files` (shared by
    /// a scene's shapes, so each file is decoded once).
    pub fn build_with(&self, key: &str, files: &BitmapFiles) -> Result<Material, SceneError> {
        if let BsdfDesc::Twosided { bsdf, front, back } = self {
            let (f, b) = match (bsdf, front, back) {
                (Some(x), None, None) => (x, x),
                (None, Some(f), Some(b)) => (f, b),
                _ => {
                    return Err(SceneError(format!(
                        "{key}: twosided takes `bsdf`, or `front` and `back`"
                    )))
                }
            };
            let side = |d: &BsdfDesc, k: &str| -> Result<Side, SceneError> {
                if matches!(d, BsdfDesc::Twosided { .. }) {
                    return Err(SceneError(format!("{k}: twosided inside twosided")));
                }
                Ok(d.build_with(k, files)?.front)
            };
            return Ok(Material {
                front: side(f, &format!("{key}.front"))?,
                back: Some(side(b, &format!("{key}.back"))?),
            });
        }
        Ok(Material {
            front: self.side(key, files)?,
            back: None,
        })
    }

    // Long because: one arm per Mitsuba BSDF plugin, each a few lines over
    // `SideContext`; the arms' field lists are most of the length.
    fn side(&self, key: &str, files: &BitmapFiles) -> Result<Side, SceneError> {
        let c = SideContext { key, files };
        let plain = |bsdf| Side {
            bsdf,
            texture: None,
        };
        match self {
            BsdfDesc::Diffuse { reflectance } => {
                let t = c.texture(reflectance, "reflectance")?;
                let reflectance = t.mean();
                Ok(textured(Bsdf::Diffuse { reflectance }, t))
            }
            BsdfDesc::Conductor {
                eta,
                k,
                material,
                specular_reflectance,
            } => c.conductor(
                [*eta, *k],
                material,
                specular_reflectance,
                Microfacet::ggx(0.0),
            ),
            BsdfDesc::Roughconductor {
                eta,
                k,
                material,
                specular_reflectance,
                alpha,
                distribution,
                sample_visible,
            } => {
                let mf = c.microfacet(*alpha, distribution, *sample_visible)?;
                c.conductor([*eta, *k], material, specular_reflectance, mf)
            }
            BsdfDesc::Dielectric { int_ior, ext_ior } => Ok(plain(Bsdf::Dielectric {
                eta: c.eta(int_ior, ext_ior)?,
                mf: Microfacet::ggx(0.0),
            })),
            BsdfDesc::Roughdielectric {
                alpha,
                distribution,
                sample_visible,
                int_ior,
                ext_ior,
            } => Ok(plain(Bsdf::Dielectric {
                eta: c.eta(int_ior, ext_ior)?,
                mf: c.microfacet(*alpha, distribution, *sample_visible)?,
            })),
            BsdfDesc::Thindielectric { int_ior, ext_ior } => Ok(plain(Bsdf::ThinDielectric {
                eta: c.eta(int_ior, ext_ior)?,
            })),
            BsdfDesc::Plastic {
                diffuse_reflectance,
                specular_reflectance,
                int_ior,
                ext_ior,
                nonlinear,
            } => {
                let (t, specular) = c.plastic_layers(diffuse_reflectance, specular_reflectance)?;
                let bsdf = Bsdf::Plastic(Plastic {
                    diffuse: t.mean(),
                    specular,
                    eta: c.eta(int_ior, ext_ior)?,
                    nonlinear: *nonlinear,
                });
                Ok(textured(bsdf, t))
            }
            BsdfDesc::Roughplastic {
                alpha,
                distribution,
                sample_visible,
                diffuse_reflectance,
                specular_reflectance,
                int_ior,
                ext_ior,
                nonlinear,
            } => {
                let (t, specular) = c.plastic_layers(diffuse_reflectance, specular_reflectance)?;
                let bsdf = Bsdf::RoughPlastic(RoughPlastic::new(
                    t.mean(),
                    specular,
                    c.eta(int_ior, ext_ior)?,
                    Microfacet {
                        alpha: alpha.max(1e-4),
                        ..c.microfacet(*alpha, distribution, *sample_visible)?
                    },
                    *nonlinear,
                ));
                Ok(textured(bsdf, t))
            }
            BsdfDesc::Null => Ok(plain(Bsdf::Null)),
            BsdfDesc::Twosided { .. } => Ok(self.build_with(key, files)?.front),
        }
    }
}

/// A side whose BSDF holds the texture's mean (for sampling weights) and
/// looks the texture itself up at each hit; a constant needs no lookup.
fn textured(bsdf: Bsdf, t: Texture) -> Side {
    match t {
        Texture::Constant(_) => Side {
            bsdf,
            texture: None,
        },
        t => Side {
            bsdf,
            texture: Some(t),
        },
    }
}

/// What building one side reads besides its description: its key (for
/// messages) and the bitmap files its textures share.
struct SideContext<'a> {
    key: &'a str,
    files: &'a BitmapFiles,
}

impl SideContext<'_> {
    fn k(&self, name: &str) -> String {
        format!("{}.{name}", self.key)
    }

    /// The relative index of refraction int/ext.
    fn eta(&self, int: &IorDesc, ext: &IorDesc) -> Result<f32, SceneError> {
        Ok(int.value(&self.k("int_ior"))? / ext.value(&self.k("ext_ior"))?)
    }

    fn microfacet(
        &self,
        alpha: f32,
        distribution: &str,
        sample_visible: bool,
    ) -> Result<Microfacet, SceneError> {
        if !(alpha.is_finite() && alpha >= 0.0) {
            return Err(SceneError(format!(
                "{}: {alpha} is not ≥ 0",
                self.k("alpha")
            )));
        }
        Ok(Microfacet {
            alpha,
            sample_visible,
            distribution: distribution_of(distribution, &self.k("distribution"))?,
        })
    }

    fn texture(&self, s: &SpectrumDesc, name: &str) -> Result<Texture, SceneError> {
        s.texture(&self.k(name), self.files)
    }

    /// A smooth or rough conductor of complex IOR (eta, k) or a named
    /// `material`, tinted by the specular reflectance.
    fn conductor(
        &self,
        [eta, k]: [Option<[f32; 3]>; 2],
        material: &Option<String>,
        specular_reflectance: &SpectrumDesc,
        mf: Microfacet,
    ) -> Result<Side, SceneError> {
        let (eta, k) =
            super::conductors::complex_ior(eta, k, material.as_deref(), &self.k("material"))?;
        let t = self.texture(specular_reflectance, "specular_reflectance")?;
        let bsdf = Bsdf::Conductor {
            eta: Vec3::from(eta),
            k: Vec3::from(k),
            mf,
            specular: t.mean(),
        };
        Ok(textured(bsdf, t))
    }

    /// A plastic's diffuse texture and constant specular reflectance (a
    /// specular texture is refused, as the coating's weight needs one
    /// value).
    fn plastic_layers(
        &self,
        diffuse: &SpectrumDesc,
        specular: &SpectrumDesc,
    ) -> Result<(Texture, Vec3), SceneError> {
        if let SpectrumDesc::Texture(_) = specular {
            return Err(SceneError(format!(
                "{}: a texture is not supported here (only for diffuse_reflectance)",
                self.k("specular_reflectance")
            )));
        }
        let t = self.texture(diffuse, "diffuse_reflectance")?;
        let specular = self.texture(specular, "specular_reflectance")?.mean();
        Ok((t, specular))
    }
}

#[cfg(test)]
mod material_test {
    use super::*;

    fn parse(s: &str) -> Result<Material, SceneError> {
        let d: BsdfDesc = toml::from_str(s).map_err(|e| SceneError(e.to_string()))?;
        d.build("shapes.0.bsdf", Path::new("."))
    }

    #[test]
    fn mitsuba_defaults_names_and_textures() {
        let m = parse(r#"type = "dielectric""#).unwrap();
        assert_eq!(
            m.front.bsdf,
            Bsdf::Dielectric {
                eta: 1.5046 / 1.000277,
                mf: Microfacet::ggx(0.0)
            }
        );
        let m = parse("type = \"dielectric\"\nint_ior = \"water\"\next_ior = 1.0").unwrap();
        assert_eq!(
            m.front.bsdf,
            Bsdf::Dielectric {
                eta: 1.333,
                mf: Microfacet::ggx(0.0)
            }
        );
        let e = parse("type = \"dielectric\"\nint_ior = \"unobtainium\"").unwrap_err();
        assert!(
            e.0.contains("shapes.0.bsdf.int_ior") && e.0.contains("unobtainium"),
            "{e}"
        );
        assert!(parse("type = \"diffuse\"\nalbedo = 0.3").is_err());
        let m = parse(
            "type = \"twosided\"\n[bsdf]\ntype = \"diffuse\"\n[bsdf.reflectance]\ntype = \"checkerboard\"\nto_uv = { scale = [2, 2] }",
        )
        .unwrap();
        let sides = |u: f32| match m.at(Vec2::new(u, 0.1)) {
            SurfaceBsdf::Two(t) => t,
            b => panic!("{b:?}"),
        };
        let diffuse = |r: f32| Bsdf::Diffuse {
            reflectance: Vec3::splat(r),
        };
        assert_eq!(sides(0.1).front, diffuse(0.4));
        assert_eq!(sides(0.3).back, diffuse(0.2));
        assert!(parse(r#"type = "null""#).unwrap().is_null());
        let e = parse("type = \"diffuse\"\nreflectance = [0.5, -1, 0]").unwrap_err();
        assert!(e.0.contains("shapes.0.bsdf.reflectance"), "{e}");
    }

    #[test]
    fn bitmap_files_and_options_are_checked() {
        let e = parse(
            r#"type = "diffuse"
               reflectance = { type = "bitmap", filename = "no_such_texture.png" }"#,
        )
        .unwrap_err();
        assert!(e.0.contains("no_such_texture.png"), "{e:?}");
        let dir = std::env::temp_dir().join(format!("fogbank_material_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        image::RgbImage::new(2, 2).save(dir.join("t.png")).unwrap();
        let d: BsdfDesc = toml::from_str(
            r#"type = "diffuse"
               reflectance = { type = "bitmap", filename = "t.png", filter_type = "cubic" }"#,
        )
        .unwrap();
        let e = d.build("shapes.0.bsdf", &dir).unwrap_err();
        assert!(
            e.0.contains("shapes.0.bsdf.reflectance") && e.0.contains("cubic"),
            "{e:?}"
        );
        let d: BsdfDesc = toml::from_str(
            r#"type = "diffuse"
               reflectance = { type = "bitmap", filename = "t.png", wrap_mode = "mirror" }"#,
        )
        .unwrap();
        let m = d.build("shapes.0.bsdf", &dir).unwrap();
        assert!(matches!(m.front.texture, Some(Texture::Bitmap(_))));
        std::fs::remove_dir_all(&dir).ok();
    }
}
