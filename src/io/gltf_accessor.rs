//! Vertex attributes of a glTF primitive read as `f32`, under glTF 2.0 (§3.7.2.1, "Meshes":
//! FLOAT positions, normals and tangents, FLOAT or normalized UNSIGNED_BYTE / UNSIGNED_SHORT
//! texture coordinates and colours) and `KHR_mesh_quantization` (what gltfpack writes by default: positions of
//! BYTE / UNSIGNED_BYTE / SHORT / UNSIGNED_SHORT, normalized or not, normals of normalized BYTE
//! or SHORT, texture coordinates of any of the four, normalized or not).
//!
//! An integer component is dequantised the way the accessor says: normalized, by glTF's
//! rule (`max(c / 127, -1)` for BYTE, `c / 255` for UNSIGNED_BYTE, and so on); not
//! normalized, as its value, which the node's transform (positions) or the material's
//! `KHR_texture_transform` (texture coordinates) then scales, as the extension prescribes.
//!
//! Before a reader is made, the accessor is checked against what reading it assumes: its
//! type and component type, a count of at least one, and strides no shorter than an
//! element (the `gltf` crate's iterators assert these, or misread where they do not hold).

use gltf::accessor::{DataType as T, Dimensions as D, Iter};

/// Why `accessor` cannot be read as `semantic` (POSITION, NORMAL, TANGENT, TEXCOORD_n, COLOR_n,
/// indices, or an instance's TRANSLATION, ROTATION or SCALE), or `None` where it can.
pub(super) fn unreadable(accessor: &gltf::Accessor<'_>, semantic: &str) -> Option<String> {
    let (d, t, normalized) = (accessor.dimensions(), accessor.data_type(), accessor.normalized());
    let fits = match semantic {
        "POSITION" => d == D::Vec3 && t != T::U32,
        "NORMAL" => d == D::Vec3 && (t == T::F32 || matches!(t, T::I8 | T::I16) && normalized),
        "TANGENT" => d == D::Vec4 && (t == T::F32 || matches!(t, T::I8 | T::I16) && normalized),
        "indices" => d == D::Scalar && matches!(t, T::U8 | T::U16 | T::U32),
        // `EXT_mesh_gpu_instancing`'s transforms (`gltf_instancing`).
        "TRANSLATION" | "SCALE" => d == D::Vec3 && t != T::U32,
        "ROTATION" => d == D::Vec4 && (t == T::F32 || matches!(t, T::I8 | T::I16) && normalized),
        s if s.starts_with("TEXCOORD_") => d == D::Vec2 && t != T::U32,
        s if s.starts_with("COLOR_") => {
            matches!(d, D::Vec3 | D::Vec4) && (t == T::F32 || matches!(t, T::U8 | T::U16) && normalized)
        }
        // Carried as they are by a scene-keeping load (`gltf_scene`): joints, weights,
        // application-specific attributes and morph-target deltas.
        s if s.starts_with("JOINTS_") => d == D::Vec4 && matches!(t, T::U8 | T::U16) && !normalized,
        s if s.starts_with("WEIGHTS_") => d == D::Vec4 && (t == T::F32 || matches!(t, T::U8 | T::U16) && normalized),
        s if s.starts_with('_') || crate::mesh::parse_morph_target(s).is_some() => {
            matches!(d, D::Scalar | D::Vec2 | D::Vec3 | D::Vec4) && t != T::U32
        }
        _ => false,
    };
    let i = accessor.index();
    if !fits {
        let component = match t {
            T::I8 => "BYTE",
            T::U8 => "UNSIGNED_BYTE",
            T::I16 => "SHORT",
            T::U16 => "UNSIGNED_SHORT",
            T::U32 => "UNSIGNED_INT",
            T::F32 => "FLOAT",
        };
        let how = if normalized || t == T::F32 { "" } else { " (not normalized)" };
        return Some(format!("{semantic} accessor {i} is {} of {component}{how}", format!("{d:?}").to_uppercase()));
    }
    layout_defect(accessor, &format!("{semantic} accessor {i}"))
}

/// Why `accessor` (named `who` in the message) does not lie where its views say: a count of
/// 0, a stride shorter than an element, elements (or sparse values and indices) past the
/// end of their view; `None` where it does.
///
/// An accessor without a buffer view is zeros (with its sparse values over them), as many
/// as its count says, however few bytes the file has: a few hundred bytes could declare
/// gigabytes. One declaring more elements than the buffer of its sparse values holds bytes
/// (a dense accessor of that count would need at least that many) is refused as such a
/// bomb. Morph targets, the usual sparse accessors, have their mesh's vertex count, which
/// its positions' bytes back.
pub(super) fn layout_defect(accessor: &gltf::Accessor<'_>, who: &str) -> Option<String> {
    if accessor.count() == 0 {
        return Some(format!("{who} has a count of 0 (glTF requires at least 1)"));
    }
    if let Some(sparse) = accessor.sparse().filter(|_| accessor.view().is_none()) {
        let backing = sparse.values().view().buffer().length();
        if accessor.count() > backing {
            return Some(format!(
                "{who} has no buffer view and declares {} elements, more than the {backing} bytes of the buffer behind its sparse values",
                accessor.count()
            ));
        }
    }
    let size = accessor.size();
    if let Some(s) = accessor.view().and_then(|v| v.stride()).filter(|&s| s < size) {
        return Some(format!("{who}'s buffer view has a stride of {s} bytes, shorter than its {size}-byte elements"));
    }
    if let Some(view) = accessor.view().filter(|v| !within(v, accessor.offset(), accessor.count(), size)) {
        return Some(format!("{who}'s {} elements run past the end of buffer view {}", accessor.count(), view.index()));
    }
    let sparse = accessor.sparse()?;
    let (indices, values) = (sparse.indices(), sparse.values());
    let index_size = indices.index_type().size();
    let short = |view: gltf::buffer::View<'_>, element: usize| view.stride().is_some_and(|s| s < element);
    if sparse.count() == 0 {
        Some(format!("{who} is sparse with a count of 0 (glTF requires at least 1)"))
    } else if short(values.view(), size) || short(indices.view(), index_size) {
        Some(format!("{who}'s sparse values or indices have a stride shorter than an element"))
    } else if !within(&values.view(), values.offset(), sparse.count(), size)
        || !within(&indices.view(), indices.offset(), sparse.count(), index_size)
    {
        Some(format!("{who}'s sparse values or indices run past the end of their buffer view"))
    } else {
        None
    }
}

/// Whether `count` elements of `size` bytes from `offset` lie inside `view` (glTF 2.0
/// §3.6.2.4), computed without overflow: the gltf crate's iterators compute the end
/// unchecked (an overflow panic in a debug build, a wrapped and possibly valid range in a
/// release one, for a count near 2^61).
fn within(view: &gltf::buffer::View<'_>, offset: usize, count: usize, size: usize) -> bool {
    let stride = view.stride().unwrap_or(size);
    let end = count.checked_sub(1).and_then(|last| last.checked_mul(stride)?.checked_add(offset)?.checked_add(size));
    end.is_some_and(|end| end <= view.length())
}

/// A component type of an accessor, and how a value of it becomes `f32`: normalized, by
/// glTF's rule (§3.11), or as its value.
trait Component: Copy + gltf::accessor::Item {
    fn dequantise(self, normalized: bool) -> f32;
}

impl Component for f32 {
    fn dequantise(self, _: bool) -> f32 {
        self
    }
}

macro_rules! integer_component {
    ($($t:ty: $max:expr),*) => {$(
        impl Component for $t {
            fn dequantise(self, normalized: bool) -> f32 {
                match normalized {
                    // max(c / 127, -1) for BYTE; c / 255 for UNSIGNED_BYTE (the max is moot).
                    true => (self as f32 / $max).max(-1.0),
                    false => f32::from(self),
                }
            }
        }
    )*};
}
integer_component!(i8: 127.0, u8: 255.0, i16: 32767.0, u16: 65535.0);

/// Values as vertex-attribute component type `component_type` (BYTE, UNSIGNED_BYTE, SHORT,
/// UNSIGNED_SHORT, normalized or not; FLOAT otherwise): the inverse of [`read`], rounded
/// and clamped to the type.
pub(super) fn encode(values: &[f32], component_type: u64, normalized: bool) -> Vec<u8> {
    let q = |x: f32, max: f32, lo: f32, hi: f32| (if normalized { x * max } else { x }).round().clamp(lo, hi);
    match component_type {
        5120 => values.iter().map(|&x| q(x, 127.0, -127.0, 127.0) as i8 as u8).collect(),
        5121 => values.iter().map(|&x| q(x, 255.0, 0.0, 255.0) as u8).collect(),
        5122 => values.iter().flat_map(|&x| (q(x, 32767.0, -32767.0, 32767.0) as i16).to_le_bytes()).collect(),
        5123 => values.iter().flat_map(|&x| (q(x, 65535.0, 0.0, 65535.0) as u16).to_le_bytes()).collect(),
        _ => values.iter().flat_map(|&x| x.to_le_bytes()).collect(),
    }
}

/// The elements of an accessor that [`unreadable`] accepted, as `f32`; `None` where its data
/// lies outside its buffer.
pub(super) fn read<'s, const N: usize>(accessor: gltf::Accessor<'s>, buffers: &'s [Vec<u8>]) -> Option<Vec<[f32; N]>>
where
    [f32; N]: gltf::accessor::Item,
    [i8; N]: gltf::accessor::Item,
    [u8; N]: gltf::accessor::Item,
    [i16; N]: gltf::accessor::Item,
    [u16; N]: gltf::accessor::Item,
{
    fn each<C: Component, const N: usize>(a: gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Option<Vec<[f32; N]>>
    where
        [C; N]: gltf::accessor::Item,
    {
        let normalized = a.normalized();
        let it = Iter::<[C; N]>::new(a, |b| buffers.get(b.index()).map(|d| &d[..]))?;
        Some(it.map(|e| e.map(|c| c.dequantise(normalized))).collect())
    }
    match accessor.data_type() {
        T::F32 => each::<f32, N>(accessor, buffers),
        T::I8 => each::<i8, N>(accessor, buffers),
        T::U8 => each::<u8, N>(accessor, buffers),
        T::I16 => each::<i16, N>(accessor, buffers),
        T::U16 => each::<u16, N>(accessor, buffers),
        T::U32 => None,
    }
}

/// The elements of a SCALAR accessor that [`unreadable`] accepted, as `f32`, dequantised as
/// [`read`] does; `None` where its data lies outside its buffer.
pub(super) fn read_scalars(accessor: gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Option<Vec<f32>> {
    fn each<C: Component>(a: gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Option<Vec<f32>> {
        let normalized = a.normalized();
        let it = Iter::<C>::new(a, |b| buffers.get(b.index()).map(|d| &d[..]))?;
        Some(it.map(|c| c.dequantise(normalized)).collect())
    }
    match accessor.data_type() {
        T::F32 => each::<f32>(accessor, buffers),
        T::I8 => each::<i8>(accessor, buffers),
        T::U8 => each::<u8>(accessor, buffers),
        T::I16 => each::<i16>(accessor, buffers),
        T::U16 => each::<u16>(accessor, buffers),
        T::U32 => None,
    }
}
