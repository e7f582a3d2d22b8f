//! GLB files built in the tests: a JSON document and its binary chunks laid out in one buffer.

use serde_json::json;

/// Little-endian bytes of a list of values.
pub fn bytes<T: Copy, const N: usize>(values: &[T], to: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| to(v)).collect()
}

/// `doc` with `chunks` laid out in one buffer, one view each (4-byte aligned), and the buffer.
pub fn pack(mut doc: serde_json::Value, chunks: &[Vec<u8>]) -> (serde_json::Value, Vec<u8>) {
    let mut bin = Vec::new();
    let mut views = Vec::new();
    for c in chunks {
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": c.len()}));
        bin.extend_from_slice(c);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
    }
    doc["bufferViews"] = json!(views);
    doc["buffers"] = json!([{"byteLength": bin.len()}]);
    (doc, bin)
}

/// A GLB of `doc` and `chunks`.
pub fn glb((doc, chunks): (serde_json::Value, Vec<Vec<u8>>)) -> Vec<u8> {
    let (doc, bin) = pack(doc, &chunks);
    let mut text = serde_json::to_vec(&doc).unwrap();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + text.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(text);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}
