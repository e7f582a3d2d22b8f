//! `EXT_mesh_gpu_instancing`: a node that draws its mesh once per instance, each under a
//! transform of its own made as a node's is (TRANSLATION × ROTATION × SCALE) and applied
//! before the node's world transform: world position = node world × instance × position
//! (the extension's "Transformation Order"). gltfpack writes it (`-mi`, as a required
//! extension), and so can Blender's and three.js's exporters.
//!
//! ```text
//!   node (world W) ── mesh M          drawn as   W·I₀·M   W·I₁·M   W·I₂·M ...
//!      └─ EXT_mesh_gpu_instancing                (the node's own copy is not drawn)
//!           TRANSLATION  t₀ t₁ t₂ ...
//!           ROTATION     q₀ q₁ q₂ ...   Iₖ = T(tₖ)·R(qₖ)·S(sₖ)
//!           SCALE        s₀ s₁ s₂ ...
//! ```
//!
//! A flattening load bakes each instance as a copy, as it bakes each node; a scene-keeping
//! load places the mesh once per instance ([`Placement::instance`](super::Placement)), and
//! its GLB output keeps the extension and its accessors as written (`write_scene`). The
//! node's children are not instanced. Application-specific instance attributes (`_ID`,
//! `_COLOR`, ...) do not move geometry: the scene-keeping output keeps them, a flattening
//! load lists them as not kept.
//!
//! The accessors are read as the extension's table says (TRANSLATION and SCALE VEC3,
//! ROTATION VEC4 of FLOAT or normalized BYTE or SHORT), and, like POSITION under
//! `KHR_mesh_quantization`, TRANSLATION and SCALE of integers too, dequantised as their
//! accessor says. A rotation is normalised (an exporter's rounding); one of length 0, and
//! any value not finite, is an error naming the node and the instance.

use glam::{DMat4, DQuat, DVec3};
use serde_json::Value;

use super::gltf::malformed;
use super::gltf_accessor::{read, unreadable};
use crate::error::LoadErrorKind;

/// The extension's name.
pub(super) const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// The transform attributes, in the order their product is taken.
const TRANSFORMS: [&str; 3] = ["TRANSLATION", "ROTATION", "SCALE"];

/// The application-specific instance attributes (`_ID`, ...) of every node.
pub(super) fn other_attributes(raw: &Value) -> std::collections::BTreeSet<String> {
    let nodes = raw.get("nodes").and_then(Value::as_array).into_iter().flatten();
    let attributes = nodes.filter_map(|n| n.pointer(&format!("/extensions/{EXTENSION}/attributes"))?.as_object());
    attributes.flat_map(|a| a.keys()).filter(|k| !TRANSFORMS.contains(&k.as_str())).cloned().collect()
}

/// How many copies of its mesh `node` draws: its instances' count as its first instance
/// attribute's accessor declares it (nothing read or checked; [`instances`] does that), else 1.
pub(super) fn declared_count(g: &gltf::Document, raw: &Value, node: &gltf::Node<'_>) -> usize {
    let attributes = raw["nodes"][node.index()].pointer(&format!("/extensions/{EXTENSION}/attributes"));
    let first = attributes.and_then(Value::as_object).and_then(|a| a.values().next()).and_then(Value::as_u64);
    first.and_then(|i| g.accessors().nth(usize::try_from(i).ok()?)).map_or(1, |a| a.count())
}

/// Each instance's transform (object → the node's space) of `node`, or `None` where it has
/// no mesh or no instancing extension (the extension defines nothing for a node without a
/// mesh). An error names the node and what is wrong: no attributes, an accessor missing or
/// of the wrong type, counts that differ, a value not finite, a rotation of length 0.
pub(super) fn instances(
    g: &gltf::Document,
    raw: &Value,
    buffers: &[Vec<u8>],
    node: &gltf::Node<'_>,
) -> Result<Option<Vec<DMat4>>, LoadErrorKind> {
    let n = node.index();
    let Some(ext) = raw["nodes"][n].get("extensions").and_then(|e| e.get(EXTENSION)) else {
        return Ok(None);
    };
    if node.mesh().is_none() {
        return Ok(None);
    }
    let here = |what: String| malformed(format!("node {n}: {EXTENSION} {what}"));
    let attributes = ext.get("attributes").and_then(Value::as_object).filter(|a| !a.is_empty());
    let attributes = attributes.ok_or_else(|| here("has no attributes".into()))?;
    let mut count = None;
    let mut accessors = std::collections::BTreeMap::new();
    for (name, index) in attributes {
        let accessor = index.as_u64().and_then(|i| g.accessors().nth(usize::try_from(i).ok()?));
        let accessor =
            accessor.ok_or_else(|| here(format!("attribute {name} names accessor {index}, which does not exist")))?;
        match count {
            None => count = Some((name, accessor.count())),
            Some((first, c)) if c != accessor.count() => {
                return Err(here(format!(
                    "attributes have different counts: {first} {c}, {name} {} (all must be the same)",
                    accessor.count()
                )));
            }
            Some(_) => {}
        }
        accessors.insert(name.as_str(), accessor);
    }
    let count = count.map_or(0, |(_, c)| c);
    let mut columns: [Option<Vec<[f32; 4]>>; 3] = [None, None, None];
    for (slot, name) in TRANSFORMS.iter().enumerate() {
        let Some(accessor) = accessors.get(name) else { continue };
        if let Some(why) = unreadable(accessor, name) {
            return Err(here(why));
        }
        let outside = || here(format!("{name} accessor {} lies outside its buffer", accessor.index()));
        columns[slot] = Some(match slot {
            1 => read::<4>(accessor.clone(), buffers).ok_or_else(outside)?,
            _ => read::<3>(accessor.clone(), buffers)
                .ok_or_else(outside)?
                .into_iter()
                .map(|[x, y, z]| [x, y, z, 0.0])
                .collect(),
        });
    }
    let [t, r, s] = &columns;
    let value = |column: &Option<Vec<[f32; 4]>>, k: usize, default: [f64; 4]| {
        column.as_ref().map_or(default, |c| c[k].map(f64::from))
    };
    let mut transforms = Vec::with_capacity(count);
    for k in 0..count {
        let parts = [value(t, k, [0.0; 4]), value(r, k, [0.0, 0.0, 0.0, 1.0]), value(s, k, [1.0; 4])];
        if let Some(i) = parts.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
            return Err(here(format!("instance {k}: its {} is not finite", TRANSFORMS[i])));
        }
        let [[tx, ty, tz, _], [x, y, z, w], [sx, sy, sz, _]] = parts;
        let q = DQuat::from_xyzw(x, y, z, w);
        if q.length() == 0.0 {
            return Err(here(format!("instance {k}: its ROTATION has length 0")));
        }
        transforms.push(DMat4::from_scale_rotation_translation(
            DVec3::new(sx, sy, sz),
            q.normalize(),
            DVec3::new(tx, ty, tz),
        ));
    }
    Ok(Some(transforms))
}
