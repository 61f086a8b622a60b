//! Typed accessor reads, checked against the spec and their buffers' bounds: positions,
//! normals, colours, texture coordinates, indices.

use glam::{Vec2, Vec3};
use gltf::Accessor;
use gltf::accessor::{DataType, Dimensions};

use super::GltfError;
use super::convert::{Importer, Site};

impl Importer<'_> {
    pub(super) fn read_positions(
        &self,
        acc: &Accessor<'_>,
        site: Site,
    ) -> Result<Vec<Vec3>, GltfError> {
        let positions = self.read_vec3(acc, "POSITION", site, None)?;
        match positions.iter().position(|p| !p.is_finite()) {
            Some(i) => Err(self.accessor_error(
                acc,
                format!(
                    "POSITION of {site}: element {i} is not finite ({})",
                    positions[i]
                ),
            )),
            None => Ok(positions),
        }
    }

    /// Checks an accessor's shape against what its semantic allows.
    pub(super) fn expect_type(
        &self,
        acc: &Accessor<'_>,
        what: &str,
        dims: &[Dimensions],
        types: &[DataType],
    ) -> Result<(), GltfError> {
        if dims.contains(&acc.dimensions()) && types.contains(&acc.data_type()) {
            return Ok(());
        }
        Err(self.accessor_error(
            acc,
            format!(
                "{what} must be {dims:?} of {types:?}, found {:?} of {:?}",
                acc.dimensions(),
                acc.data_type()
            ),
        ))
    }

    /// Checks that an attribute has one element per vertex.
    pub(super) fn expect_count(
        &self,
        acc: &Accessor<'_>,
        what: &str,
        expected: Option<usize>,
    ) -> Result<(), GltfError> {
        match expected {
            Some(n) if acc.count() != n => Err(self.accessor_error(
                acc,
                format!("{what} has {} elements but POSITION has {n}", acc.count()),
            )),
            _ => Ok(()),
        }
    }

    /// Reads a float VEC3 attribute.
    pub(super) fn read_vec3(
        &self,
        acc: &Accessor<'_>,
        semantic: &str,
        site: Site,
        expected: Option<usize>,
    ) -> Result<Vec<Vec3>, GltfError> {
        let what = format!("{semantic} of {site}");
        self.expect_type(acc, &what, &[Dimensions::Vec3], &[DataType::F32])?;
        self.expect_count(acc, &what, expected)?;
        let raw = self.read_raw(acc)?;
        Ok(raw
            .chunks_exact(3)
            .map(|c| {
                Vec3::new(
                    f32::from_bits(c[0]),
                    f32::from_bits(c[1]),
                    f32::from_bits(c[2]),
                )
            })
            .collect())
    }

    /// Reads `COLOR_0` (RGB or RGBA; float or normalised u8/u16) as RGBA.
    pub(super) fn read_colors(
        &self,
        acc: &Accessor<'_>,
        count: usize,
        site: Site,
    ) -> Result<Vec<[f32; 4]>, GltfError> {
        let what = format!("COLOR_0 of {site}");
        let dims = [Dimensions::Vec3, Dimensions::Vec4];
        let types = [DataType::F32, DataType::U8, DataType::U16];
        self.expect_type(acc, &what, &dims, &types)?;
        self.expect_count(acc, &what, Some(count))?;
        let scale = match acc.data_type() {
            DataType::U8 => Some(255.0),
            DataType::U16 => Some(65535.0),
            _ => None,
        };
        let values: Vec<f32> = self
            .read_raw(acc)?
            .into_iter()
            .map(|bits| scale.map_or(f32::from_bits(bits), |s| bits as f32 / s))
            .collect();
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.accessor_error(acc, format!("{what}: value {i} is not finite")));
        }
        let width = acc.dimensions().multiplicity();
        Ok(values
            .chunks_exact(width)
            .map(|c| [c[0], c[1], c[2], c.get(3).copied().unwrap_or(1.0)])
            .collect())
    }

    /// Reads `TEXCOORD_0` (float, or normalised u8/u16 as the spec allows) as UVs.
    pub(super) fn read_uvs(
        &self,
        acc: &Accessor<'_>,
        count: usize,
        site: Site,
    ) -> Result<Vec<Vec2>, GltfError> {
        let what = format!("TEXCOORD_0 of {site}");
        let types = [DataType::F32, DataType::U8, DataType::U16];
        self.expect_type(acc, &what, &[Dimensions::Vec2], &types)?;
        self.expect_count(acc, &what, Some(count))?;
        let scale = match acc.data_type() {
            DataType::U8 => Some(255.0),
            DataType::U16 => Some(65535.0),
            _ => None,
        };
        if scale.is_some() && !acc.normalized() {
            return Err(self.accessor_error(
                acc,
                format!(
                    "{what}: integer texture coordinates must be normalized (`\"normalized\": \
                     true`)"
                ),
            ));
        }
        let values: Vec<f32> = self
            .read_raw(acc)?
            .into_iter()
            .map(|bits| scale.map_or(f32::from_bits(bits), |s| bits as f32 / s))
            .collect();
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.accessor_error(acc, format!("{what}: value {i} is not finite")));
        }
        Ok(values
            .chunks_exact(2)
            .map(|c| Vec2::new(c[0], c[1]))
            .collect())
    }

    /// Reads an index accessor and checks every index is below `vertex_count`.
    pub(super) fn read_indices(
        &self,
        acc: &Accessor<'_>,
        vertex_count: usize,
        site: Site,
    ) -> Result<Vec<u32>, GltfError> {
        let what = format!("indices of {site}");
        let types = [DataType::U8, DataType::U16, DataType::U32];
        self.expect_type(acc, &what, &[Dimensions::Scalar], &types)?;
        let indices = self.read_raw(acc)?;
        match indices.iter().position(|&i| i as usize >= vertex_count) {
            Some(at) => Err(self.accessor_error(
                acc,
                format!(
                    "{what}: index {} (element {at}) is out of range; there are {vertex_count} \
                     vertices",
                    indices[at]
                ),
            )),
            None => Ok(indices),
        }
    }

    /// Every component of every element as a little-endian `u32` (float bits for `F32`), after
    /// checking the accessor lies within its buffer view and the view within its buffer.
    pub(super) fn read_raw(&self, acc: &Accessor<'_>) -> Result<Vec<u32>, GltfError> {
        let (region, stride) = self.accessor_region(acc)?;
        let size = acc.data_type().size();
        let width = acc.dimensions().multiplicity();
        let mut out = Vec::with_capacity(acc.count() * width);
        for element in region.chunks(stride) {
            out.extend(element.chunks_exact(size).take(width).map(le_component));
        }
        Ok(out)
    }

    /// The bytes from the accessor's first element to the end of its last, and the stride.
    pub(super) fn accessor_region(&self, acc: &Accessor<'_>) -> Result<(&[u8], usize), GltfError> {
        if acc.sparse().is_some() {
            return Err(self.unsupported(format!("sparse accessor {}", acc.index())));
        }
        let Some(view) = acc.view() else {
            return Err(self.accessor_error(acc, "has no buffer view".into()));
        };
        let element = acc.size();
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(self.accessor_error(
                acc,
                format!("byte stride {stride} is smaller than one element ({element} bytes)"),
            ));
        }
        let view_bytes = self.view_bytes(&view)?;
        if acc.count() == 0 {
            return Ok((&[], stride));
        }
        let end = (acc.count() - 1)
            .checked_mul(stride)
            .and_then(|n| n.checked_add(element))
            .and_then(|n| n.checked_add(acc.offset()));
        let region = end.and_then(|end| view_bytes.get(acc.offset()..end));
        let region = region.ok_or_else(|| {
            self.accessor_error(
                acc,
                format!(
                    "out of bounds: {} elements of {element} bytes (stride {stride}) from byte \
                     {} do not fit in buffer view {} ({} bytes)",
                    acc.count(),
                    acc.offset(),
                    view.index(),
                    view_bytes.len()
                ),
            )
        })?;
        Ok((region, stride))
    }

    /// A buffer view's bytes, checked against its buffer's actual length.
    pub(super) fn view_bytes(&self, view: &gltf::buffer::View<'_>) -> Result<&[u8], GltfError> {
        let buffer = view.buffer().index();
        let data = self.buffers.get(buffer).map_or(&[][..], |b| &b[..]);
        let range = view.offset()..view.offset().saturating_add(view.length());
        data.get(range.clone()).ok_or_else(|| {
            self.invalid(format!(
                "buffer view {} (bytes {range:?}) is out of bounds of buffer {buffer} ({} bytes)",
                view.index(),
                data.len()
            ))
        })
    }
}

/// One little-endian component of 1, 2 or 4 bytes.
pub(super) fn le_component(bytes: &[u8]) -> u32 {
    bytes
        .iter()
        .rev()
        .fold(0, |acc, &b| (acc << 8) | u32::from(b))
}
