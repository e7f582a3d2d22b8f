//! Buffer views compressed with meshoptimizer's codecs: the glTF extensions
//! `EXT_meshopt_compression` and `KHR_meshopt_compression`, which gltfpack's `-c` writes
//! (Khronos glTF extension registry, `EXT_meshopt_compression` §"Decoding" and
//! `KHR_meshopt_compression`, which adds the version 1 vertex codec and the `COLOR` filter).
//!
//! Such a view says where its compressed bytes are (`buffer`, `byteOffset`, `byteLength`),
//! how many elements of `byteStride` bytes they hold, the codec (`mode`: `ATTRIBUTES`,
//! `TRIANGLES` or `INDICES`) and the filter applied after it (`NONE`, `OCTAHEDRAL`,
//! `QUATERNION`, `EXPONENTIAL`, `COLOR`). The view itself points into a *fallback* buffer,
//! which a GLB leaves without data (or with the same data uncompressed, `gltfpack -cf`). The
//! decoded bytes are written there, at each view's own offset, so that every accessor then
//! reads its view as in an uncompressed file. The decoding itself is meshoptimizer's own,
//! through the `meshopt` crate: the reference implementation of both codecs, which is safe
//! on untrusted input (a malformed stream is an error or garbage, never a read outside it).

use super::gltf::malformed;
use crate::error::LoadErrorKind;

/// The two names of the extension; their view objects have the same properties.
pub(super) const EXTENSIONS: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// The most bytes a compressed view may decode to per byte of its stream. meshoptimizer's
/// version 1 vertex codec spends a byte of control on 4 byte columns of up to 256 vertices
/// where they are all zero (1,024 to 1); no real stream comes near it. It bounds what a
/// few bytes of a hostile file can make the loader allocate.
const MAX_RATIO: usize = 1024;

/// Whether buffer `index` of the JSON is a fallback for compressed views: its data, if it
/// has any, is not read; [`decode_views`] fills it.
pub(super) fn is_fallback(raw: &serde_json::Value, index: usize) -> bool {
    let extensions = &raw["buffers"][index]["extensions"];
    EXTENSIONS.iter().any(|e| extensions.get(e).is_some())
}

/// One compressed view's properties, as its extension object states them.
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: String,
    filter: String,
}

impl Compressed {
    fn read(view: usize, ext: &serde_json::Value) -> Result<Self, LoadErrorKind> {
        let number = |key: &str, default: Option<usize>| {
            match ext.get(key) {
                None => default,
                Some(v) => v.as_u64().and_then(|n| usize::try_from(n).ok()),
            }
            .ok_or_else(|| malformed(format!("buffer view {view}: its meshopt compression has no valid {key}")))
        };
        let word = |key: &str, default: Option<&str>| {
            match ext.get(key) {
                None => default,
                Some(v) => v.as_str(),
            }
            .map(str::to_string)
            .ok_or_else(|| malformed(format!("buffer view {view}: its meshopt compression has no valid {key}")))
        };
        Ok(Compressed {
            buffer: number("buffer", None)?,
            offset: number("byteOffset", Some(0))?,
            length: number("byteLength", None)?,
            stride: number("byteStride", None)?,
            count: number("count", None)?,
            mode: word("mode", None)?,
            filter: word("filter", Some("NONE"))?,
        })
    }

    /// Why this view's stride, mode and filter do not go together (the extension's
    /// "Mode and filter" rules), or `None` where they do; `khr` allows the `COLOR` filter.
    fn defect(&self, khr: bool) -> Option<String> {
        let (s, filter) = (self.stride, self.filter.as_str());
        match self.mode.as_str() {
            "ATTRIBUTES" if s == 0 || s % 4 != 0 || s > 256 => {
                Some(format!("ATTRIBUTES need a byteStride that is a multiple of 4 up to 256, not {s}"))
            }
            "ATTRIBUTES" => match filter {
                "NONE" | "EXPONENTIAL" => None,
                "OCTAHEDRAL" if s == 4 || s == 8 => None,
                "QUATERNION" if s == 8 => None,
                "COLOR" if khr && (s == 4 || s == 8) => None,
                "OCTAHEDRAL" | "QUATERNION" => Some(format!("the {filter} filter does not take a byteStride of {s}")),
                "COLOR" if khr => Some(format!("the COLOR filter does not take a byteStride of {s}")),
                _ => Some(format!("unknown filter {filter:?}")),
            },
            "TRIANGLES" | "INDICES" if s != 2 && s != 4 => {
                Some(format!("{} need a byteStride of 2 or 4, not {s}", self.mode))
            }
            "TRIANGLES" if self.count % 3 != 0 => {
                Some(format!("TRIANGLES need a count divisible by 3, not {}", self.count))
            }
            "TRIANGLES" | "INDICES" if filter != "NONE" => Some(format!("{} take no filter, not {filter}", self.mode)),
            "TRIANGLES" | "INDICES" => None,
            mode => Some(format!("unknown mode {mode:?}")),
        }
    }

    /// `stream` (this view's compressed bytes) decoded into `out`, `count × stride` bytes.
    fn decode(&self, stream: &[u8], out: &mut [u8]) -> Result<(), String> {
        let why = |e: meshopt::Error| format!("its {} stream does not decode ({e:?})", self.mode);
        let mut put = |values: &[u8]| out.copy_from_slice(values);
        match (self.mode.as_str(), self.stride) {
            ("TRIANGLES", 2) => {
                put(bytemuck::cast_slice(&meshopt::decode_index_buffer::<u16>(stream, self.count).map_err(why)?))
            }
            ("TRIANGLES", _) => {
                put(bytemuck::cast_slice(&meshopt::decode_index_buffer::<u32>(stream, self.count).map_err(why)?))
            }
            ("INDICES", 2) => {
                put(bytemuck::cast_slice(&meshopt::decode_index_sequence::<u16>(stream, self.count).map_err(why)?))
            }
            ("INDICES", _) => {
                put(bytemuck::cast_slice(&meshopt::decode_index_sequence::<u32>(stream, self.count).map_err(why)?))
            }
            _ => {
                // Decoded as 32-bit words, which the filters read in place (a buffer's bytes
                // need not be aligned for them).
                let mut words = vec![0u32; self.count * self.stride / 4];
                // SAFETY: `words` holds count × stride bytes, which is what the decoder writes
                // for `count` vertices of `stride` bytes; it reads at most `stream.len()` bytes
                // of `stream`.
                let code = unsafe {
                    meshopt::ffi::meshopt_decodeVertexBuffer(
                        words.as_mut_ptr().cast(),
                        self.count,
                        self.stride,
                        stream.as_ptr(),
                        stream.len(),
                    )
                };
                if code != 0 {
                    return Err(format!("its ATTRIBUTES stream does not decode (meshoptimizer's code {code})"));
                }
                self.unfilter(&mut words);
                put(bytemuck::cast_slice(&words));
            }
        }
        Ok(())
    }

    /// The filter undone in place over the decoded vertices (`defect` checked the stride).
    fn unfilter(&self, data: &mut [u32]) {
        let as_bytes: &mut [u8] = bytemuck::cast_slice_mut(data);
        match (self.filter.as_str(), self.stride) {
            ("OCTAHEDRAL", 4) => meshopt::decode_filter_oct::<i8>(bytemuck::cast_slice_mut(as_bytes)),
            ("OCTAHEDRAL", _) => meshopt::decode_filter_oct::<i16>(bytemuck::cast_slice_mut(as_bytes)),
            ("QUATERNION", _) => meshopt::decode_filter_quat(bytemuck::cast_slice_mut(as_bytes)),
            // Each 32-bit component is decoded on its own, whatever the stride.
            ("EXPONENTIAL", _) => meshopt::decode_filter_exp::<1>(bytemuck::cast_slice_mut(as_bytes)),
            ("COLOR", 4) => meshopt::decode_filter_color::<u8>(bytemuck::cast_slice_mut(as_bytes)),
            ("COLOR", _) => meshopt::decode_filter_color::<u16>(bytemuck::cast_slice_mut(as_bytes)),
            _ => {}
        }
    }
}

/// Decodes every compressed view of `raw` into its fallback buffer (a compressed view over a
/// buffer that holds data is read as that data). `buffers` holds every
/// buffer's data, with an empty vector for each fallback (`is_fallback`); `declared` each
/// buffer's byteLength. Every view is checked before anything is allocated: its mode,
/// stride and filter consistent, its stream inside a buffer that holds data, its decoded
/// size equal to the view's `byteLength` and at most [`MAX_RATIO`] times its stream. A
/// fallback buffer then comes out at its declared length, which must hold its views and not
/// pass the last of them by more than 4 KiB of padding. A view of a fallback buffer that is
/// not compressed has nothing to read: an error too.
pub(super) fn decode_views(
    raw: &serde_json::Value,
    declared: &[usize],
    buffers: &mut [Vec<u8>],
) -> Result<(), LoadErrorKind> {
    let fallback: Vec<bool> = (0..buffers.len()).map(|b| is_fallback(raw, b)).collect();
    let views = raw.get("bufferViews").and_then(|v| v.as_array()).map_or(&[][..], Vec::as_slice);
    // (view, its extension's name, what it states, its target buffer, where it goes there)
    let mut jobs = Vec::new();
    for (i, view) in views.iter().enumerate() {
        let target = view["buffer"].as_u64().and_then(|b| usize::try_from(b).ok()).filter(|&b| b < buffers.len());
        let (name, ext) = match EXTENSIONS.iter().find_map(|e| Some((*e, view["extensions"].get(e)?))) {
            Some(found) => found,
            None if target.is_some_and(|b| fallback[b]) => {
                return Err(malformed(format!(
                    "buffer view {i} lies in fallback buffer {}, which holds only decoded views, but is not compressed",
                    view["buffer"]
                )))
            }
            None => continue,
        };
        let c = Compressed::read(i, ext)?;
        let fail = |why: String| malformed(format!("buffer view {i} ({name}): {why}"));
        if let Some(why) = c.defect(name == EXTENSIONS[1]) {
            return Err(fail(why));
        }
        let Some(target) = target else {
            return Err(fail(format!("it lies in buffer {}, which the file does not have", view["buffer"])));
        };
        // Over a buffer that holds data (not a fallback), the view's bytes are already there,
        // uncompressed, as glTF itself lays them out: nothing to decode.
        if !fallback[target] {
            continue;
        }
        if c.buffer >= buffers.len() || fallback[c.buffer] {
            return Err(fail(format!("its stream is in buffer {}, which holds no data", c.buffer)));
        }
        if c.offset.checked_add(c.length).is_none_or(|end| end > buffers[c.buffer].len()) {
            return Err(fail(format!(
                "its stream ({} bytes from {}) runs past the end of buffer {}",
                c.length, c.offset, c.buffer
            )));
        }
        let size = c.count.saturating_mul(c.stride);
        let length = view["byteLength"].as_u64().and_then(|n| usize::try_from(n).ok());
        if length != Some(size) {
            let stated = &view["byteLength"];
            return Err(fail(format!(
                "{} elements of {} bytes do not fill its byteLength of {stated}",
                c.count, c.stride
            )));
        }
        if size > c.length.saturating_mul(MAX_RATIO).saturating_add(4096) {
            return Err(fail(format!("{size} bytes cannot come from a stream of {}", c.length)));
        }
        let offset = view["byteOffset"].as_u64().map_or(Some(0), |n| usize::try_from(n).ok());
        let place = offset.and_then(|o| Some(o..o.checked_add(size)?)).filter(|r| r.end <= declared[target]);
        let Some(place) = place else {
            return Err(fail(format!("it runs past the end of buffer {target}")));
        };
        jobs.push((i, name, c, target, place));
    }
    // The fallback buffers get their length before any view writes into them.
    for (b, data) in buffers.iter_mut().enumerate().filter(|(b, _)| fallback[*b]) {
        let reach = jobs.iter().filter(|job| job.3 == b).map(|job| job.4.end).max().unwrap_or(0);
        if declared[b] > reach.saturating_add(4096) {
            return Err(malformed(format!(
                "fallback buffer {b} declares {} bytes, but its compressed views end at {reach}",
                declared[b]
            )));
        }
        *data = vec![0; declared[b]];
    }
    // Each view decoded into its place (a fallback buffer; its stream is in another one).
    for (i, name, c, target, place) in jobs {
        let mut fallback = std::mem::take(&mut buffers[target]);
        let stream = &buffers[c.buffer][c.offset..c.offset + c.length];
        let decoded = c.decode(stream, &mut fallback[place]);
        buffers[target] = fallback;
        decoded.map_err(|why| malformed(format!("buffer view {i} ({name}): {why}")))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A document with one data buffer holding `stream` and one fallback buffer, its view 0
    /// compressed as `ext` says (buffer, byteLength and byteOffset filled in).
    fn one_view(
        stream: &[u8],
        count: usize,
        stride: usize,
        mode: &str,
        name: &str,
    ) -> (serde_json::Value, Vec<Vec<u8>>) {
        let raw = json!({
            "buffers": [{"byteLength": stream.len()}, {"byteLength": count * stride, "extensions": {name: {"fallback": true}}}],
            "bufferViews": [{"buffer": 1, "byteLength": count * stride, "extensions": {name: {
                "buffer": 0, "byteLength": stream.len(), "byteStride": stride, "count": count, "mode": mode}}}],
        });
        (raw, vec![stream.to_vec(), Vec::new()])
    }

    fn decode(raw: &serde_json::Value, mut buffers: Vec<Vec<u8>>) -> Result<Vec<u8>, String> {
        let declared: Vec<usize> =
            raw["buffers"].as_array().unwrap().iter().map(|b| b["byteLength"].as_u64().unwrap() as usize).collect();
        decode_views(raw, &declared, &mut buffers).map_err(|e| e.to_string())?;
        Ok(buffers.pop().unwrap())
    }

    /// 32-bit indices (more than 65,535 vertices, which no fixture has), by both index codecs.
    #[test]
    fn four_byte_indices_decode() {
        let indices: Vec<u32> = (0..300u32).map(|i| [0, 70_000 + i, 70_001 + i][(i % 3) as usize] + i / 3).collect();
        let triangles = meshopt::encode_index_buffer(&indices, 71_000).unwrap();
        let sequence = meshopt::encode_index_sequence(&indices, 71_000).unwrap();
        for (stream, mode) in [(triangles, "TRIANGLES"), (sequence, "INDICES")] {
            let (raw, buffers) = one_view(&stream, indices.len(), 4, mode, EXTENSIONS[0]);
            let bytes = decode(&raw, buffers).unwrap();
            let back: Vec<u32> = bytes.chunks(4).map(|c| u32::from_le_bytes(c.try_into().unwrap())).collect();
            match mode {
                // The triangle codec may start a triangle at another of its corners.
                "TRIANGLES" => {
                    let turned = |t: &[u32]| {
                        let k = (0..3).min_by_key(|&k| t[k]).unwrap();
                        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
                    };
                    let a: Vec<_> = back.chunks(3).map(turned).collect();
                    assert_eq!(a, indices.chunks(3).map(turned).collect::<Vec<_>>());
                }
                _ => assert_eq!(back, indices),
            }
        }
    }

    /// Vertices of 12 bytes with the exponential filter: each 32-bit component decoded on its
    /// own (what gltfpack's `-vpf` positions use), and the view placed at its own offset.
    #[test]
    fn vertices_decode_at_their_view_offset() {
        let values: Vec<[u32; 3]> = (0..40u32).map(|i| [i, 1000 + i * 7, u32::MAX - i]).collect();
        let stream = meshopt::encode_vertex_buffer(&values).unwrap();
        let (mut raw, buffers) = one_view(&stream, 40, 12, "ATTRIBUTES", EXTENSIONS[1]);
        raw["buffers"][1]["byteLength"] = json!(40 * 12 + 16);
        raw["bufferViews"][0]["byteOffset"] = json!(16);
        let bytes = decode(&raw, buffers).unwrap();
        assert_eq!(&bytes[..16], &[0; 16]);
        assert_eq!(&bytes[16..], bytemuck::cast_slice::<[u32; 3], u8>(&values));
    }

    #[test]
    fn inconsistent_views_are_named() {
        let values: Vec<[u8; 4]> = (0..16u8).map(|i| [i, i, i, i]).collect();
        let stream = meshopt::encode_vertex_buffer(&values).unwrap();
        let refuse = |change: &dyn Fn(&mut serde_json::Value), why: &str| {
            let (mut raw, buffers) = one_view(&stream, 16, 4, "ATTRIBUTES", EXTENSIONS[0]);
            change(&mut raw);
            let e = decode(&raw, buffers).unwrap_err();
            assert!(e.contains(why), "{e}, not {why}");
        };
        fn ext(raw: &mut serde_json::Value) -> &mut serde_json::Value {
            &mut raw["bufferViews"][0]["extensions"][EXTENSIONS[0]]
        }
        refuse(
            &|r| ext(r)["byteStride"] = json!(6),
            "ATTRIBUTES need a byteStride that is a multiple of 4 up to 256, not 6",
        );
        refuse(&|r| ext(r)["filter"] = json!("QUATERNION"), "the QUATERNION filter does not take a byteStride of 4");
        refuse(&|r| ext(r)["filter"] = json!("COLOR"), "unknown filter \"COLOR\"");
        refuse(&|r| ext(r)["mode"] = json!("STRIPS"), "unknown mode \"STRIPS\"");
        refuse(&|r| ext(r)["mode"] = json!("TRIANGLES"), "TRIANGLES need a count divisible by 3, not 16");
        refuse(&|r| ext(r)["count"] = json!(-1), "its meshopt compression has no valid count");
        refuse(&|r| ext(r)["buffer"] = json!(1), "its stream is in buffer 1, which holds no data");
        refuse(&|r| ext(r)["byteOffset"] = json!(u64::MAX), "runs past the end of buffer 0");
        refuse(
            &|r| r["bufferViews"][0]["byteLength"] = json!(60),
            "16 elements of 4 bytes do not fill its byteLength of 60",
        );
        refuse(&|r| r["bufferViews"][0]["byteOffset"] = json!(8), "it runs past the end of buffer 1");
        refuse(&|r| r["bufferViews"][0]["buffer"] = json!(7), "it lies in buffer 7, which the file does not have");
        // A few bytes that would decode to gigabytes are refused before anything is allocated.
        refuse(
            &|r| {
                // A terabyte: allocating it first would abort the test.
                ext(r)["count"] = json!(1u64 << 38);
                r["bufferViews"][0]["byteLength"] = json!(1u64 << 40);
                r["buffers"][1]["byteLength"] = json!(1u64 << 40);
            },
            "1099511627776 bytes cannot come from a stream of",
        );
    }
}
