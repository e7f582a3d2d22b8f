//! Writers: OBJ, binary little-endian PLY and GLB. [`save`] writes to a temporary file in the
//! destination folder and renames it into place, so readers never see half a file and a
//! failure leaves the old file (if any) untouched. Every writer first checks the mesh
//! ([`IndexedMesh::check`]): an index past the vertices, a non-finite position, an attribute
//! or primitive list of the wrong length would otherwise come out as a file no reader can
//! use (or a panic halfway through).

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use serde_json::json;

use crate::mesh::origin::InFile;
use crate::mesh::IndexedMesh;

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WriteFormat {
    /// Wavefront OBJ with `vt`/`vn` and vertex colours when present, one `o` block per
    /// primitive; [`save`] writes the materials beside it (an MTL library and the textures,
    /// `write_mtl.rs`).
    Obj,
    /// Binary little-endian PLY with normals, UVs and colours when present (UVs in double
    /// where turning v over for the file's bottom-left origin would not fit f32).
    Ply,
    /// Binary glTF: one mesh, one glTF primitive per primitive, shared vertex arrays.
    Glb,
}

impl WriteFormat {
    /// The format an output path's extension names.
    pub fn from_path(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            "glb" => Some(Self::Glb),
            _ => None,
        }
    }
}

/// What of `mesh` a file in `format` cannot hold, as phrases ("vertex attributes TANGENT,
/// TEXCOORD_1", "materials", ...); empty when nothing is lost. GLB holds everything a mesh
/// carries; OBJ holds vertex colours (`COLOR_0` without its alpha) but no other further
/// attribute, and the materials as far as MTL can (`write_mtl.rs` lists what it cannot);
/// PLY holds `COLOR_0` too, and the primitives' base-colour textures where each has one
/// (`texture_files.rs`, MeshLab's form), but no other material, nor a split into primitives
/// beyond one per texture. Neither can
/// leave colours out of some primitives only: those come out black. Callers print it, so
/// that no output loses data silently.
pub fn not_written(mesh: &IndexedMesh, format: WriteFormat) -> Vec<String> {
    let mut out = Vec::new();
    let scene_only: Vec<&str> =
        mesh.attributes.iter().filter(|a| a.scene_only()).map(|a| a.semantic.as_str()).collect();
    if format == WriteFormat::Glb {
        if !scene_only.is_empty() {
            out.push(format!(
                "{} (joints, weights and morph targets need their glTF scene: save the GltfScene to keep them)",
                scene_only.join(", ")
            ));
        }
        return out;
    }
    let dropped: Vec<&str> =
        mesh.attributes.iter().filter(|a| a.semantic != "COLOR_0").map(|a| a.semantic.as_str()).collect();
    if !dropped.is_empty() {
        out.push(format!("vertex attributes {}", dropped.join(", ")));
    }
    if let Some(colour) = mesh.attributes.iter().find(|a| a.semantic == "COLOR_0") {
        if format == WriteFormat::Obj && colour.components == 4 {
            out.push("the alpha of COLOR_0 (OBJ vertex colours are RGB)".into());
        }
        if !colour.absent.is_empty() {
            // OBJ readers refuse a file where only some vertices have colours; PLY has no
            // primitives to leave it out of.
            out.push(format!(
                "that COLOR_0 is missing from {} primitive(s): their vertices are written black",
                colour.absent.len()
            ));
        }
    }
    if format == WriteFormat::Obj {
        out.extend(super::write_mtl::library(mesh, "").map(|lib| lib.lost).unwrap_or_default());
    } else if let Some(textures) = super::texture_files::ply_textures(mesh, "") {
        if !super::texture_files::texture_alone(mesh) {
            out.push("the materials but their base-colour textures, which TextureFile names (write .glb or .obj to keep them)".into());
        }
        if format == WriteFormat::Ply && textures.files.0.len() < mesh.primitives.len() {
            out.push(format!(
                "the split into {} primitives (PLY keeps one per texture, {})",
                mesh.primitives.len(),
                textures.files.0.len()
            ));
        }
        return out;
    } else if mesh.gltf_materials.as_ref().is_some_and(|m| m.materials.as_array().is_some_and(|a| !a.is_empty())) {
        out.push("materials (write .glb or .obj to keep them)".into());
    }
    if format == WriteFormat::Ply && mesh.primitives.len() > 1 {
        out.push(format!("the split into {} primitives (PLY has one mesh)", mesh.primitives.len()));
    }
    out
}

/// Writes `mesh` to `path` in the format its extension names (`.obj`, `.ply`, `.glb`); returns
/// the files written, `path` last (an OBJ's materials come first: its MTL library and
/// textures, beside it).
pub fn save(path: impl AsRef<Path>, mesh: &IndexedMesh) -> io::Result<Vec<PathBuf>> {
    let path = path.as_ref();
    let format = WriteFormat::from_path(path).ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}: cannot write this extension (use .obj, .ply or .glb)", path.display()),
        )
    })?;
    save_as(path, mesh, format)
}

/// Writes `mesh` to `path` in `format`, each file atomically; returns the files written, as
/// [`save`] does. An OBJ whose primitives have materials gets an MTL library named after it
/// (`lod1.obj`: `lod1.mtl`) and the textures the library names (`lod1_wood.png`), written
/// before it, so that an OBJ is never seen without them. A library of that name that dynlod
/// did not write (an OBJ simplified in place, `a.obj` to `a.obj`, keeps its `a.mtl`) is
/// left as it is, and the OBJ's gets the next free name (`a_1.mtl`).
pub fn save_as(path: impl AsRef<Path>, mesh: &IndexedMesh, format: WriteFormat) -> io::Result<Vec<PathBuf>> {
    let path = path.as_ref();
    writable(mesh)?;
    let mut written = Vec::new();
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let mut library = (format == WriteFormat::Obj).then(|| super::write_mtl::library(mesh, &stem)).flatten();
    if let Some(lib) = &mut library {
        lib.file = library_name(path, &lib.file);
    }
    let ply_textures = (format == WriteFormat::Ply).then(|| super::texture_files::ply_textures(mesh, &stem)).flatten();
    // Texture images first, then the library: a reader never finds a file without what it names.
    let images = library.as_ref().map(|lib| &lib.textures).or(ply_textures.as_ref().map(|t| &t.files));
    if let (Some(images), Some(mats)) = (images, &mesh.gltf_materials) {
        for (file, image) in &images.0 {
            written.push(path.with_file_name(file));
            let bytes = mats.images[*image].bytes.as_deref().unwrap_or_default();
            atomically(&written[written.len() - 1], |w| w.write_all(bytes))?;
        }
    }
    if let Some(lib) = &library {
        written.push(path.with_file_name(&lib.file));
        atomically(&written[written.len() - 1], |w| w.write_all(lib.text.as_bytes()))?;
    }
    atomically(path, |w| match format {
        WriteFormat::Obj => obj(w, mesh, library.as_ref()),
        WriteFormat::Ply => ply(w, mesh, ply_textures.as_ref()),
        WriteFormat::Glb => write_glb(w, mesh),
    })?;
    written.push(path.to_path_buf());
    Ok(written)
}

/// The name of the MTL library an OBJ output at `path` gets where that name is free or
/// dynlod's (`lod 1.obj`: `lod_1.mtl`); [`save_as`] takes the next one (`lod_1_1.mtl`)
/// where a library of that name is someone else's.
pub fn library_name_for(path: impl AsRef<Path>) -> String {
    let stem = path.as_ref().file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    format!("{}.mtl", super::texture_files::word(&stem))
}

/// `file` (an MTL library's name, `stem.mtl`) beside `path`, where no file of that name is
/// there or dynlod wrote the one that is (its first line says so); else the first
/// `stem_k.mtl` that is free or dynlod's: a user's own library is never replaced.
fn library_name(path: &Path, file: &str) -> String {
    let ours = |name: &str| {
        let mut head = [0u8; 20];
        let mut f = match std::fs::File::open(path.with_file_name(name)) {
            Ok(f) => f,
            Err(e) => return e.kind() == io::ErrorKind::NotFound,
        };
        let n = std::io::Read::read(&mut f, &mut head).unwrap_or(0);
        head[..n].starts_with(super::write_mtl::SIGNATURE.as_bytes())
    };
    let stem = file.strip_suffix(".mtl").unwrap_or(file);
    std::iter::once(file.to_string())
        .chain((1..).map(|k| format!("{stem}_{k}.mtl")))
        .find(|f| ours(f))
        .expect("unbounded")
}

/// Runs `write` into a temporary file beside `path` and renames it into place: readers never
/// see half a file, and a failure leaves whatever was at `path` untouched. The file gets the
/// permissions of the one it replaces, or those a newly created file gets (0666 less the
/// umask on Unix), not the temporary file's owner-only 0600.
pub(super) fn atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&std::fs::File>) -> io::Result<()>,
) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".dynlod-").suffix(".tmp");
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder.tempfile_in(dir)?;
    if let Ok(old) = std::fs::metadata(path) {
        tmp.as_file().set_permissions(old.permissions())?;
    }
    {
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w)?;
        w.flush()?;
    }
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// The mesh's first defect as an [`io::ErrorKind::InvalidInput`] error that wraps the typed
/// [`crate::error::MeshError`] (reach it with `get_ref()` and `downcast_ref`).
pub(super) fn writable(m: &IndexedMesh) -> io::Result<()> {
    m.check().map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))
}

/// OBJ text, without materials ([`save`] writes them beside the file).
pub fn write_obj(w: &mut impl Write, m: &IndexedMesh) -> io::Result<()> {
    obj(w, m, None)
}

/// OBJ text, naming `library` and its materials where given.
fn obj(w: &mut impl Write, m: &IndexedMesh, library: Option<&super::write_mtl::Library>) -> io::Result<()> {
    writable(m)?;
    writeln!(w, "# written by dynlod {}", env!("CARGO_PKG_VERSION"))?;
    if let Some(lib) = library {
        writeln!(w, "mtllib {}", lib.file)?;
    }
    // Vertex colours as the common `v x y z r g b` extension (Blender, MeshLab, tobj).
    let colour = m.attributes.iter().find(|a| a.semantic == "COLOR_0");
    // Relative to a far origin, each coordinate is its decimal sum with the origin's.
    for (i, p) in m.positions.iter().enumerate() {
        let [x, y, z] = [0, 1, 2].map(|k| InFile(m.origin[k], p[k]));
        match colour {
            Some(c) => {
                let c = c.get(i);
                writeln!(w, "v {x} {y} {z} {} {} {}", c[0], c[1], c[2])?
            }
            None => writeln!(w, "v {x} {y} {z}")?,
        }
    }
    for t in &m.uvs {
        writeln!(w, "vt {} {}", t[0], super::uv_origin::to_bottom_left(t[1]))?;
    }
    for n in &m.normals {
        writeln!(w, "vn {} {} {}", n[0], n[1], n[2])?;
    }
    let (has_t, has_n) = (!m.uvs.is_empty(), !m.normals.is_empty());
    // Faces grouped by primitive, each group in the mesh's order: OBJ starts an object at
    // every `o` and `usemtl`, so a primitive whose faces lie apart (a glTF mesh drawn by two
    // nodes, or any after a spatial reordering) would come back as many objects.
    let mut order: Vec<usize> = (0..m.triangles.len()).collect();
    if m.primitives.len() > 1 {
        order.sort_by_key(|&i| m.primitive_of(i));
    }
    let mut current = u32::MAX;
    for (i, t) in order.into_iter().map(|i| (i, &m.triangles[i])) {
        let p = m.primitive_of(i);
        if p != current && m.primitives.len() > 1 {
            let name = m.primitives.get(p as usize).map(|x| x.name.as_str()).unwrap_or("");
            writeln!(
                w,
                "o {}",
                if name.is_empty() { format!("primitive_{p}") } else { name.replace(char::is_whitespace, "_") }
            )?;
        }
        if let (true, Some(lib)) = (p != current, library) {
            // A primitive without a material (or one past the list) gets the library's last,
            // glTF's default material.
            let material = m.primitives.get(p as usize).and_then(|x| x.material);
            let name = material.and_then(|k| lib.names.get(k)).or(lib.names.last());
            writeln!(w, "usemtl {}", name.map_or("", String::as_str))?;
        }
        current = p;
        // A primitive whose source had no UVs or normals gets none here either.
        let source = m.primitives.get(p as usize);
        let has_t = has_t && !source.is_some_and(|x| x.no_uvs);
        let has_n = has_n && !source.is_some_and(|x| x.no_normals);
        write!(w, "f")?;
        for &v in t {
            let v = v + 1;
            match (has_t, has_n) {
                (false, false) => write!(w, " {v}")?,
                (true, false) => write!(w, " {v}/{v}")?,
                (false, true) => write!(w, " {v}//{v}")?,
                (true, true) => write!(w, " {v}/{v}/{v}")?,
            }
        }
        writeln!(w)?;
    }
    Ok(())
}

/// Binary little-endian PLY, naming no texture ([`save`] names them where it can).
pub fn write_ply(w: &mut impl Write, m: &IndexedMesh) -> io::Result<()> {
    ply(w, m, None)
}

/// Binary little-endian PLY, naming `textures` as MeshLab does where given: a
/// `comment TextureFile` each; with more than one, texture coordinates per face corner
/// (`texcoord`, f32) and a texture number per face (`texnumber`) instead of per vertex.
fn ply(w: &mut impl Write, m: &IndexedMesh, textures: Option<&super::texture_files::PlyTextures>) -> io::Result<()> {
    writable(m)?;
    let corners = textures.is_some_and(|t| t.files.0.len() > 1);
    let (has_t, has_n) = (!m.uvs.is_empty() && !corners, !m.normals.is_empty());
    writeln!(w, "ply\nformat binary_little_endian 1.0\ncomment written by dynlod {}", env!("CARGO_PKG_VERSION"))?;
    for (file, _) in textures.map_or(&[][..], |t| &t.files.0[..]) {
        writeln!(w, "comment TextureFile {file}")?;
    }
    // Relative to a far origin, positions are written in double, the origin added back.
    let far = m.origin != [0.0; 3];
    let position_type = if far { "double" } else { "float" };
    writeln!(w, "element vertex {}", m.positions.len())?;
    for axis in ["x", "y", "z"] {
        writeln!(w, "property {position_type} {axis}")?;
    }
    if has_n {
        writeln!(w, "property float nx\nproperty float ny\nproperty float nz")?;
    }
    // Texture coordinates turn over (`uv_origin.rs`), each v once for the vertices and the
    // face corners alike; in double where some v would not read back the same from f32.
    let flipped: Vec<f32> = m.uvs.iter().map(|&[_, v]| super::uv_origin::to_bottom_left_f32(v)).collect();
    let holds = |(&f, &[_, v]): (&f32, &[f32; 2])| super::uv_origin::reads_back(f64::from(f), v);
    let uv_double = has_t && !flipped.iter().zip(&m.uvs).all(holds);
    if has_t {
        let uv_type = if uv_double { "double" } else { "float" };
        writeln!(w, "property {uv_type} u\nproperty {uv_type} v")?;
    }
    let colour = m.attributes.iter().find(|a| a.semantic == "COLOR_0");
    if let Some(c) = colour {
        let channels = ["red", "green", "blue", "alpha"];
        for name in &channels[..c.components] {
            writeln!(w, "property uchar {name}")?;
        }
    }
    writeln!(w, "element face {}\nproperty list uchar int vertex_indices", m.triangles.len())?;
    if corners {
        writeln!(w, "property list uchar float texcoord\nproperty int texnumber")?;
    }
    writeln!(w, "end_header")?;
    for i in 0..m.positions.len() {
        let normal = m.normals.get(i).map_or(&[][..], |n| &n[..]);
        if far {
            for (x, o) in m.positions[i].iter().zip(m.origin) {
                w.write_all(&(f64::from(*x) + o).to_le_bytes())?;
            }
        } else {
            for x in &m.positions[i] {
                w.write_all(&x.to_le_bytes())?;
            }
        }
        for x in normal {
            w.write_all(&x.to_le_bytes())?;
        }
        if let (true, Some((&[u, v], &flipped))) = (has_t, m.uvs.get(i).zip(flipped.get(i))) {
            if uv_double {
                w.write_all(&f64::from(u).to_le_bytes())?;
                w.write_all(&super::uv_origin::to_bottom_left(v).to_le_bytes())?;
            } else {
                w.write_all(&u.to_le_bytes())?;
                w.write_all(&flipped.to_le_bytes())?;
            }
        }
        if let Some(c) = colour {
            // Colours read from 8-bit channels come back to the same bytes.
            for &x in c.get(i) {
                w.write_all(&[(x.clamp(0.0, 1.0) * 255.0).round() as u8])?;
            }
        }
    }
    for (i, t) in m.triangles.iter().enumerate() {
        w.write_all(&[3])?;
        for &v in t {
            w.write_all(&(v as i32).to_le_bytes())?;
        }
        if let (true, Some(textures)) = (corners, textures) {
            w.write_all(&[6])?;
            for &v in t {
                w.write_all(&m.uvs[v as usize][0].to_le_bytes())?;
                w.write_all(&flipped[v as usize].to_le_bytes())?;
            }
            let number = textures.number.get(m.primitive_of(i) as usize).copied().unwrap_or(0);
            w.write_all(&(number as i32).to_le_bytes())?;
        }
    }
    Ok(())
}

/// `n` scaled to unit length where it is off by more than 0.1 % (glTF requires unit normals
/// and tangents; OBJ files often hold others, which renderers normalise anyway); as it is
/// where it is close enough, bit for bit, or zero.
pub(super) fn unit(n: [f32; 3]) -> [f32; 3] {
    // In f64: the squares of a tiny f32 vector's components (1e-22) are subnormal or zero in
    // f32, and a length computed from them is not its length.
    let length = n.iter().map(|&c| f64::from(c).powi(2)).sum::<f64>().sqrt();
    if length > 0.0 && (length - 1.0).abs() > 1e-3 {
        n.map(|c| (f64::from(c) / length) as f32)
    } else {
        n
    }
}

/// A tangent as glTF requires it: [`unit()`] xyz, handedness ±1.
pub(super) fn unit_tangent([x, y, z, w]: [f32; 4]) -> [f32; 4] {
    let [x, y, z] = unit([x, y, z]);
    [x, y, z, if w < 0.0 { -1.0 } else { 1.0 }]
}

/// A NORMAL or TANGENT accessor's elements, as glTF requires them (§3.7.2.1): unit vectors
/// throughout. Each element goes through `fix`; and since the primitives share the vertex
/// arrays, a vertex that only primitives without the attribute (`present(p)` false) draw
/// holds zeros, so it gets `placeholder`, which no primitive reads.
fn unit_elements<const N: usize>(
    m: &IndexedMesh,
    elements: impl Iterator<Item = [f32; N]>,
    present: impl Fn(u32) -> bool,
    placeholder: [f32; N],
    fix: impl Fn([f32; N]) -> [f32; N],
) -> Vec<u8> {
    let mut drawn = Vec::new();
    if !(0..m.primitives.len().max(1) as u32).all(&present) {
        drawn = vec![false; m.positions.len()];
        for (i, t) in m.triangles.iter().enumerate() {
            if present(m.primitive_of(i)) {
                t.iter().for_each(|&v| drawn[v as usize] = true);
            }
        }
    }
    let element = |(i, e)| if drawn.get(i) == Some(&false) { placeholder } else { fix(e) };
    elements.enumerate().flat_map(element).flat_map(f32::to_le_bytes).collect()
}

/// Binary glTF 2.0: one mesh, one glTF primitive per primitive, shared vertex arrays; with a
/// glTF source, its materials, textures, samplers and images (embedded) come along and each
/// primitive keeps its material.
pub fn write_glb(w: &mut impl Write, m: &IndexedMesh) -> io::Result<()> {
    writable(m)?;
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, data: &[u8], target: u32| -> usize {
        let offset = bin.len();
        bin.extend_from_slice(data);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target}));
        views.len() - 1
    };
    let f32_bytes = |v: &mut dyn Iterator<Item = f32>| -> Vec<u8> { v.flat_map(f32::to_le_bytes).collect() };
    let (lo, hi) = crate::mesh::bounds(m.positions.iter().copied());
    let pos_view = push_view(&mut bin, &f32_bytes(&mut m.positions.iter().flatten().copied()), 34962);
    accessors.push(json!({"bufferView": pos_view, "componentType": 5126, "count": m.positions.len(), "type": "VEC3", "min": lo, "max": hi}));
    let mut attributes = serde_json::Map::new();
    attributes.insert("POSITION".into(), json!(0));
    if !m.normals.is_empty() {
        let present = |p: u32| !m.primitives.get(p as usize).is_some_and(|x| x.no_normals);
        let bytes = unit_elements(m, m.normals.iter().copied(), present, [0.0, 0.0, 1.0], unit);
        let v = push_view(&mut bin, &bytes, 34962);
        accessors.push(json!({"bufferView": v, "componentType": 5126, "count": m.normals.len(), "type": "VEC3"}));
        attributes.insert("NORMAL".into(), json!(accessors.len() - 1));
    }
    if !m.uvs.is_empty() {
        let v = push_view(&mut bin, &f32_bytes(&mut m.uvs.iter().flatten().copied()), 34962);
        accessors.push(json!({"bufferView": v, "componentType": 5126, "count": m.uvs.len(), "type": "VEC2"}));
        attributes.insert("TEXCOORD_0".into(), json!(accessors.len() - 1));
    }
    for a in m.attributes.iter().filter(|a| !a.scene_only()) {
        let bytes = if a.semantic == "TANGENT" {
            let tangents = a.values.chunks_exact(4).map(|t| [t[0], t[1], t[2], t[3]]);
            unit_elements(m, tangents, |p| a.present_in(p), [1.0, 0.0, 0.0, 1.0], unit_tangent)
        } else {
            f32_bytes(&mut a.values.iter().copied())
        };
        let v = push_view(&mut bin, &bytes, 34962);
        let kind = ["SCALAR", "VEC2", "VEC3", "VEC4"][a.components - 1];
        accessors.push(json!({"bufferView": v, "componentType": 5126, "count": a.len(), "type": kind}));
        attributes.insert(a.semantic.clone(), json!(accessors.len() - 1));
    }
    // Each primitive's indices, in one pass over the triangles (a pass per primitive cost
    // primitives × triangles: minutes for a CAD export of thousands of parts).
    let nprim = m.primitives.len().max(1);
    let mut by_primitive = vec![Vec::new(); nprim];
    for (i, t) in m.triangles.iter().enumerate() {
        by_primitive[m.primitive_of(i) as usize].extend(t.iter().flat_map(|v| v.to_le_bytes()));
    }
    let mut prims = Vec::new();
    for (p, idx) in by_primitive.into_iter().enumerate() {
        if idx.is_empty() {
            continue;
        }
        let v = push_view(&mut bin, &idx, 34963);
        accessors.push(json!({"bufferView": v, "componentType": 5125, "count": idx.len() / 4, "type": "SCALAR"}));
        // A primitive whose source had no normals or UVs gets none here either.
        let mut attrs = attributes.clone();
        if let Some(source) = m.primitives.get(p) {
            if source.no_normals {
                attrs.remove("NORMAL");
            }
            if source.no_uvs {
                attrs.remove("TEXCOORD_0");
            }
        }
        for a in m.attributes.iter().filter(|a| !a.present_in(p as u32) && !a.scene_only()) {
            attrs.remove(&a.semantic);
        }
        let mut prim = json!({"attributes": attrs, "indices": accessors.len() - 1, "mode": 4});
        let material = m.primitives.get(p).and_then(|x| x.material);
        if let (Some(mat), Some(mats)) = (material, &m.gltf_materials) {
            if mats.materials.as_array().is_some_and(|a| mat < a.len()) {
                prim["material"] = json!(mat);
            }
        }
        prims.push(prim);
    }
    // Materials of a glTF source: images go into the binary chunk, the rest is copied as it
    // was (indices between materials, textures, samplers and images are unchanged).
    let mut images = Vec::new();
    if let Some(mats) = &m.gltf_materials {
        for img in &mats.images {
            let mut j = serde_json::Map::new();
            if let Some(n) = &img.name {
                j.insert("name".into(), json!(n));
            }
            match (&img.bytes, &img.uri) {
                (Some(b), _) => {
                    let offset = bin.len();
                    bin.extend_from_slice(b);
                    while bin.len() % 4 != 0 {
                        bin.push(0);
                    }
                    views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": b.len()}));
                    j.insert("bufferView".into(), json!(views.len() - 1));
                    j.insert("mimeType".into(), json!(img.mime_type.clone().unwrap_or_else(|| "image/png".into())));
                }
                (None, Some(uri)) => {
                    j.insert("uri".into(), json!(uri));
                }
                (None, None) => {}
            }
            images.push(serde_json::Value::Object(j));
        }
    }
    let name = m.primitives.first().map(|p| p.name.clone()).unwrap_or_default();
    // Positions relative to a far origin keep their precision in f32; the node carries the
    // origin, glTF's own way, as JSON numbers in full (our reader, and any that reads them in
    // double, places the mesh exactly; one that reads f32 within half its step).
    let mut node = json!({"mesh": 0});
    if m.origin != [0.0; 3] {
        node["translation"] = json!(m.origin);
    }
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": concat!("dynlod ", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [node],
        "meshes": [{"name": name, "primitives": prims}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    if let Some(mats) = &m.gltf_materials {
        let non_empty = |v: &serde_json::Value| v.as_array().is_some_and(|a| !a.is_empty());
        for (key, value) in [("materials", &mats.materials), ("textures", &mats.textures), ("samplers", &mats.samplers)]
        {
            if non_empty(value) {
                doc[key] = value.clone();
            }
        }
        if !images.is_empty() {
            doc["images"] = json!(images);
        }
        if !mats.extensions_used.is_empty() {
            doc["extensionsUsed"] = json!(mats.extensions_used);
        }
        if !mats.extensions_required.is_empty() {
            doc["extensionsRequired"] = json!(mats.extensions_required);
        }
    }
    glb_container(w, &doc, &bin)
}

/// A GLB file: the 12-byte header, the JSON chunk (`doc`) and the BIN chunk (`bin`, whose
/// length is a multiple of 4).
pub(super) fn glb_container(w: &mut impl Write, doc: &serde_json::Value, bin: &[u8]) -> io::Result<()> {
    let mut json_bytes = serde_json::to_vec(doc).map_err(io::Error::other)?;
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let total = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let Ok(total) = u32::try_from(total) else {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("a GLB of {total} bytes is past the format's limit of 4 GiB (its lengths are 32-bit)"),
        ));
    };
    w.write_all(b"glTF")?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&total.to_le_bytes())?;
    w.write_all(&(json_bytes.len() as u32).to_le_bytes())?;
    w.write_all(b"JSON")?;
    w.write_all(&json_bytes)?;
    w.write_all(&(bin.len() as u32).to_le_bytes())?;
    w.write_all(b"BIN\0")?;
    w.write_all(bin)?;
    Ok(())
}
