//! Materials' textures: a primitive's base-colour and normal textures as [`SurfaceMaps`], their
//! images decoded once per file and shared, their samplers; the texture features of a
//! material that are not imported are reported.

use std::sync::Arc;

use glam::Vec2;
use gltf::material::Material;
use gltf::texture::{MagFilter, WrappingMode};
use texel_geom::texture::{Filter, Image, Sampler, SurfaceMaps, TextureRef, Wrap};

use crate::read::FileKind;
use crate::texture::{TextureError, decode_texture};

use super::GltfError;
use super::buffers::{read_uri, short, source_label};
use super::convert::{Importer, Site};

impl Importer<'_> {
    /// The textures of `material` as one primitive samples them; `has_uvs`: the primitive has
    /// `TEXCOORD_0`. Only the base-colour and normal textures are imported; the others are
    /// reported.
    pub(super) fn surface_maps(
        &self,
        material: &Material<'_>,
        has_uvs: bool,
        site: Site,
    ) -> Result<SurfaceMaps, GltfError> {
        let label = material_label(material);
        let pbr = material.pbr_metallic_roughness();
        let ignored = [
            (
                pbr.metallic_roughness_texture().is_some(),
                "metallic-roughness",
            ),
            (material.occlusion_texture().is_some(), "occlusion"),
            (material.emissive_texture().is_some(), "emissive"),
        ];
        for (_, kind) in ignored.iter().filter(|(used, _)| *used) {
            self.warn(&format!("{kind} texture"), || {
                format!("{kind} textures ignored (first in {label})")
            });
        }
        let albedo = match pbr.base_color_texture() {
            Some(info) => {
                self.texture_ref(&info.texture(), info.tex_coord(), "base-colour", &label)?
            }
            None => None,
        };
        let normal = match material.normal_texture() {
            Some(info) => {
                let scale = info.scale();
                if scale != 1.0 {
                    self.warn("normal texture scale", || {
                        format!(
                            "normal texture scale ignored (first {scale} in {label}): normal \
                             maps apply at scale 1"
                        )
                    });
                }
                self.texture_ref(&info.texture(), info.tex_coord(), "normal", &label)?
            }
            None => None,
        };
        let maps = SurfaceMaps {
            albedo,
            normal,
            uv_scale: Vec2::ONE,
        };
        if !maps.is_empty() && !has_uvs {
            self.warn("textures without TEXCOORD_0", || {
                format!(
                    "{site} has textures but no TEXCOORD_0: its UVs are all 0, so each texture \
                     shows one pixel"
                )
            });
        }
        Ok(maps)
    }

    /// A texture as a surface uses it, or `None` (reported) when it reads a texture coordinate
    /// set other than `TEXCOORD_0`.
    fn texture_ref(
        &self,
        texture: &gltf::Texture<'_>,
        tex_coord: u32,
        role: &str,
        material: &str,
    ) -> Result<Option<TextureRef>, GltfError> {
        if tex_coord != 0 {
            self.warn("texCoord", || {
                format!(
                    "textures on TEXCOORD_1 or above ignored (first: the {role} texture of \
                     {material}, on TEXCOORD_{tex_coord}): only TEXCOORD_0 is imported"
                )
            });
            return Ok(None);
        }
        Ok(Some(TextureRef {
            image: self.image(texture.source().index())?,
            sampler: sampler(&texture.sampler()),
        }))
    }

    /// Image `index`, decoded on first use and shared afterwards; charged against the image
    /// budget.
    fn image(&self, index: usize) -> Result<Arc<Image>, GltfError> {
        if let Some(image) = self.images.borrow().get(&index) {
            return Ok(image.clone());
        }
        let fail = |detail: String| GltfError::Image {
            path: self.name.to_path_buf(),
            index,
            detail,
        };
        let decode_detail = |e: TextureError| match e {
            TextureError::Decode { detail, .. } => detail,
            other => other.to_string(),
        };
        let Some(json) = self.document.as_json().images.get(index) else {
            return Err(self.invalid(format!("image {index} does not exist")));
        };
        let mut name = format!("{} image {index}", self.name.display());
        if let Some(own) = &json.name {
            name += &format!(" {:?}", short(own));
        }
        let decoded = match (&json.buffer_view, &json.uri) {
            (Some(view), _) => {
                let Some(view) = self.document.views().nth(view.value()) else {
                    return Err(fail(format!("buffer view {} does not exist", view.value())));
                };
                decode_texture(self.view_bytes(&view)?, &name).map_err(decode_detail)
            }
            (None, Some(uri)) => {
                let bytes = read_uri(
                    uri,
                    self.base_dir,
                    self.limits.allow_any_uri,
                    FileKind::Texture,
                )
                .map_err(fail)?;
                decode_texture(&bytes, &name).map_err(|e| {
                    let from = source_label(gltf::buffer::Source::Uri(uri), self.base_dir);
                    format!("{from}: {}", decode_detail(e))
                })
            }
            (None, None) => Err("has neither a uri nor a bufferView".to_owned()),
        };
        let image = decoded.map_err(fail)?;
        let total = self
            .image_bytes
            .get()
            .saturating_add(image.pixels.len() as u64);
        if total > self.max_image_bytes {
            return Err(GltfError::Budget {
                path: self.name.to_path_buf(),
                detail: format!(
                    "its images decode to more than {} bytes (image {index} brings the total to \
                     {total}; set TEXEL_GLTF_MAX_IMAGE_BYTES to raise the limit)",
                    self.max_image_bytes
                ),
            });
        }
        self.image_bytes.set(total);
        let image = Arc::new(image);
        self.images.borrow_mut().insert(index, image.clone());
        Ok(image)
    }
}

/// How the engine samples a glTF sampler: `magFilter` NEAREST or absent → nearest (pixel art's
/// default), LINEAR → linear; `minFilter` is not read (the one filter serves magnification
/// and minification alike); `wrapS` / `wrapT` → the wrap along U / V.
pub(super) fn sampler(s: &gltf::texture::Sampler<'_>) -> Sampler {
    let wrap = |mode| match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    };
    Sampler {
        filter: match s.mag_filter() {
            Some(MagFilter::Linear) => Filter::Linear,
            Some(MagFilter::Nearest) | None => Filter::Nearest,
        },
        wrap: [wrap(s.wrap_s()), wrap(s.wrap_t())],
    }
}

/// `material 2 "Brick"`, for messages.
fn material_label(material: &Material<'_>) -> String {
    match (material.index(), material.name()) {
        (Some(i), Some(name)) => format!("material {i} {:?}", short(name)),
        (Some(i), None) => format!("material {i}"),
        (None, _) => "the default material".to_owned(),
    }
}
