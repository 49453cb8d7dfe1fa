//! glTF 2.0 writer: `.glb` (binary container) and `.gltf` (JSON, buffer embedded).
//!
//! The JSON is built with `serde_json` rather than the `gltf` crate's `gltf-json` types:
//! the document needs only a dozen object kinds, `serde_json` is small, and its output
//! is deterministic (object keys in a fixed order, floats printed by the shortest
//! round-trip rule), which the byte-identical-builds promise rests on.
//!
//! Conventions (glTF 2.0 spec, section 3.4): metres, right-handed, +Y up, front faces
//! counter-clockwise. Press coordinates are millimetres with +Z up, so a point or normal
//! `(x, y, z)` maps to `(x, z, -y)`, positions also divided by 1000. The map is a
//! rotation (determinant +1), so windings keep facing the same way.
//!
//! Layout: one buffer; every accessor has its own tightly packed buffer view (no
//! `byteStride` needed), each view starts on a 4-byte boundary. Positions are `f32`
//! `VEC3` with exact `min`/`max` (computed on the `f32` values the buffer holds), normals
//! `f32` unit `VEC3`, indices `u16` when every index fits below the primitive-restart
//! value 65535 and `u32` otherwise. Triangles are mode 4, curves mode 3 (`LINE_STRIP`).
//! One material per declaration kind present, double-sided (die faces are open sheets).
//! Every node has `extras` { name, kind, line, tolerance_mm, source }; a draw bead's node
//! also has `line_bead` { points_mm (press coordinates, Z up), spacing_mm, force_n_per_mm }.
//! A primitive whose triangles are grouped (a solid's faces) has `extras.groups`, each
//! { name, triangles: [[first, count], ...] } in the primitive's triangle numbers.

use std::collections::HashMap;
use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;
use serde_json::{json, Map, Value};

use super::scene::{Geometry, Node, Scene};

/// `componentType` values (glTF 2.0, 3.6.2.2).
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const FLOAT: u32 = 5126;
/// `bufferView.target` values.
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// Primitive modes.
const MODE_LINE_STRIP: u32 = 3;
const MODE_TRIANGLES: u32 = 4;

/// GLB header and chunk magic numbers (glTF 2.0, section 4.4).
const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const GLB_VERSION: u32 = 2;
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"

/// The scene as a binary glTF (`.glb`): 12-byte header, a JSON chunk padded with
/// spaces, and a BIN chunk padded with zeros (absent when there is no geometry).
pub fn encode_glb(scene: &Scene) -> Vec<u8> {
    encode_glb_with(scene, &mut GltfCache::default())
}

/// [`encode_glb`], taking the buffer bytes of tessellations encoded before from `cache`
/// (what `dieface watch` keeps between saves).
pub fn encode_glb_with(scene: &Scene, cache: &mut GltfCache) -> Vec<u8> {
    let doc = Document::build(scene, cache);
    let mut json = serde_json::to_vec(&doc.json(None)).expect("a JSON value always serializes");
    pad(&mut json, b' ');
    let mut bin = doc.buffer;
    pad(&mut bin, 0);
    let mut total = 12 + 8 + json.len();
    if !bin.is_empty() {
        total += 8 + bin.len();
    }
    let mut out = Vec::with_capacity(total);
    for word in [GLB_MAGIC, GLB_VERSION, total as u32] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    out
}

/// The scene as a JSON glTF (`.gltf`), pretty-printed, with the buffer embedded as a
/// base64 data URI so the file stands alone.
pub fn encode_gltf(scene: &Scene) -> Vec<u8> {
    encode_gltf_with(scene, &mut GltfCache::default())
}

/// [`encode_gltf`], taking the buffer bytes of tessellations encoded before from
/// `cache`.
pub fn encode_gltf_with(scene: &Scene, cache: &mut GltfCache) -> Vec<u8> {
    let doc = Document::build(scene, cache);
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64(&doc.buffer)
    );
    let mut out =
        serde_json::to_vec_pretty(&doc.json(Some(uri))).expect("a JSON value always serializes");
    out.push(b'\n');
    out
}

/// A vertex the GLB cannot hold faithfully: the node (its name and source line) and
/// the coordinate (press mm).
#[derive(Debug, Clone, PartialEq)]
pub struct OutOfRange {
    /// The node's name (`binder/front`).
    pub part: String,
    /// The node's source line.
    pub line: usize,
    /// The offending coordinate, in press mm.
    pub coordinate: f64,
}

/// The first vertex of the scene that is not finite or lies beyond
/// [`crate::geom::MAX_COORDINATE`] in some axis: the GLB's `f32` metres would hold it
/// as infinity, or round it by more than the default tolerance. The writer itself
/// cannot fail; a build calls this first and refuses such a scene with a diagnostic at
/// the declaration.
pub fn out_of_range(scene: &Scene) -> Option<OutOfRange> {
    scene.all_nodes().into_iter().find_map(|node| {
        node.geometry.iter().find_map(|g| {
            let points = match g.as_ref() {
                Geometry::Triangles { positions, .. } => positions,
                Geometry::LineStrip { points } => points,
            };
            points
                .iter()
                .flat_map(|p| p.to_array())
                .find(|c| !c.is_finite() || c.abs() > crate::geom::MAX_COORDINATE)
                .map(|coordinate| OutOfRange {
                    part: node.name.clone(),
                    line: node.line,
                    coordinate,
                })
        })
    })
}

/// Press millimetres to glTF metres, +Y up.
pub fn to_gltf_position(p: DVec3) -> [f32; 3] {
    // `+ 0.0` turns a negative zero (from `-y` with y = 0) into a plain zero.
    [p.x / 1000.0, p.z / 1000.0, -p.y / 1000.0].map(|c| c as f32 + 0.0)
}

/// A press direction to glTF axes (unit length kept).
pub fn to_gltf_direction(n: DVec3) -> [f32; 3] {
    let n = n.try_normalize().unwrap_or(DVec3::Z);
    [n.x, n.z, -n.y].map(|c| c as f32 + 0.0)
}

/// The buffer bytes of tessellations already encoded, kept between encodings by the
/// tessellation they were made from (the scene cache hands back the same shared
/// tessellation for a piece that did not change): a rebuild that changed one piece
/// converts only that piece's vertices. Each entry holds its tessellation, so its
/// address cannot be reused while it is listed; entries an encoding did not use are
/// dropped after it.
#[derive(Default)]
pub struct GltfCache {
    entries: EncodedMap,
}

impl GltfCache {
    /// Converts every tessellation of `scene` not in the cache yet, each on its own
    /// (in parallel: a cold build converts a few hundred thousand vertices), so the
    /// document is then assembled from the cache in order.
    fn prepare(&mut self, scene: &Scene) {
        fn walk<'a>(node: &'a Node, out: &mut Vec<&'a Arc<Geometry>>) {
            out.extend(node.geometry.iter().filter(|g| !g.is_empty()));
            for child in &node.children {
                walk(child, out);
            }
        }
        let mut all = Vec::new();
        for node in &scene.nodes {
            walk(node, &mut all);
        }
        let cached = |g: &Arc<Geometry>| {
            self.entries
                .get(&(Arc::as_ptr(g) as usize))
                .is_some_and(|(kept, _)| Arc::ptr_eq(kept, g))
        };
        let mut seen = std::collections::HashSet::new();
        let missing: Vec<&Arc<Geometry>> = all
            .into_iter()
            .filter(|g| !cached(g) && seen.insert(Arc::as_ptr(g) as usize))
            .collect();
        let converted: Vec<Arc<Encoded>> = missing
            .par_iter()
            .map(|g| Arc::new(Encoded::of(g)))
            .collect();
        for (g, e) in missing.into_iter().zip(converted) {
            self.entries
                .insert(Arc::as_ptr(g) as usize, ((*g).clone(), e));
        }
    }

    /// The encoded bytes of `g`, from the cache or converted now; kept in `used`.
    fn encoded(&self, g: &Arc<Geometry>, used: &mut EncodedMap) -> Arc<Encoded> {
        let at = Arc::as_ptr(g) as usize;
        let encoded = match self.entries.get(&at) {
            Some((kept, e)) if Arc::ptr_eq(kept, g) => e.clone(),
            _ => Arc::new(Encoded::of(g)),
        };
        used.insert(at, (g.clone(), encoded.clone()));
        encoded
    }
}

/// One tessellation's buffer bytes, as the glTF accessors hold them: positions in glTF
/// metres with their exact `f32` bounds, unit normals (triangles only) and indices
/// (`u16` when every index fits, else `u32`; triangles only).
struct Encoded {
    positions: Vec<u8>,
    vertex_count: usize,
    lo: [f32; 3],
    hi: [f32; 3],
    normals: Vec<u8>,
    indices: Vec<u8>,
    index_count: usize,
    small_indices: bool,
}

impl Encoded {
    /// Converts a tessellation's vertices (and normals and indices) to buffer bytes.
    fn of(g: &Geometry) -> Encoded {
        match g {
            Geometry::Triangles {
                positions,
                normals,
                indices,
                ..
            } => {
                let (bytes, lo, hi) = vec3_bytes(positions.iter().map(|&p| to_gltf_position(p)));
                let dirs = (0..positions.len())
                    .map(|i| to_gltf_direction(normals.get(i).copied().unwrap_or(DVec3::Z)));
                let small = positions.len() < usize::from(u16::MAX);
                Encoded {
                    positions: bytes,
                    vertex_count: positions.len(),
                    lo,
                    hi,
                    normals: vec3_bytes(dirs).0,
                    indices: index_bytes(indices, small),
                    index_count: indices.len(),
                    small_indices: small,
                }
            }
            Geometry::LineStrip { points } => {
                let (bytes, lo, hi) = vec3_bytes(points.iter().map(|&p| to_gltf_position(p)));
                Encoded {
                    positions: bytes,
                    vertex_count: points.len(),
                    lo,
                    hi,
                    normals: Vec::new(),
                    indices: Vec::new(),
                    index_count: 0,
                    small_indices: true,
                }
            }
        }
    }
}

/// `VEC3` floats as little-endian bytes, with their bounds.
fn vec3_bytes(data: impl ExactSizeIterator<Item = [f32; 3]>) -> (Vec<u8>, [f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    let mut bytes = Vec::with_capacity(data.len() * 12);
    for v in data {
        for k in 0..3 {
            bytes.extend_from_slice(&v[k].to_le_bytes());
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    (bytes, lo, hi)
}

/// Indices as little-endian `u16` (`small`) or `u32`.
fn index_bytes(indices: &[u32], small: bool) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(indices.len() * if small { 2 } else { 4 });
    for &i in indices {
        if small {
            bytes.extend_from_slice(&(i as u16).to_le_bytes());
        } else {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
    }
    bytes
}

/// The encoded tessellations an encoding used, by address.
type EncodedMap = HashMap<usize, (Arc<Geometry>, Arc<Encoded>)>;

/// The glTF document being assembled: JSON arrays and the binary buffer.
#[derive(Default)]
struct Document {
    nodes: Vec<Value>,
    roots: Vec<usize>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    material_kinds: Vec<String>,
    accessors: Vec<Value>,
    views: Vec<Value>,
    buffer: Vec<u8>,
    tolerance_mm: f64,
    source: String,
}

impl Document {
    fn build(scene: &Scene, cache: &mut GltfCache) -> Document {
        let mut doc = Document {
            tolerance_mm: scene.tolerance_mm,
            source: scene.source_name.clone(),
            ..Document::default()
        };
        cache.prepare(scene);
        let mut used = HashMap::new();
        for node in &scene.nodes {
            let i = doc.node(node, cache, &mut used);
            doc.roots.push(i);
        }
        cache.entries = used;
        doc
    }

    /// Adds `node` and its descendants (parents first); returns its index.
    fn node(&mut self, node: &Node, cache: &GltfCache, used: &mut EncodedMap) -> usize {
        let index = self.nodes.len();
        self.nodes.push(Value::Null);
        let mut obj = Map::new();
        obj.insert("name".into(), json!(node.name));
        if let Some(mesh) = self.mesh(node, cache, used) {
            obj.insert("mesh".into(), json!(mesh));
        }
        let children: Vec<usize> = node
            .children
            .iter()
            .map(|c| self.node(c, cache, used))
            .collect();
        if !children.is_empty() {
            obj.insert("children".into(), json!(children));
        }
        let mut extras = json!({
            "name": node.name,
            "kind": node.kind,
            "line": node.line,
            "tolerance_mm": self.tolerance_mm,
            "source": self.source,
        });
        if let (Some(lb), Value::Object(map)) = (&node.line_bead, &mut extras) {
            let points: Vec<[f64; 3]> = lb.points.iter().map(|p| [p.x, p.y, p.z]).collect();
            map.insert(
                "line_bead".into(),
                json!({
                    "points_mm": points,
                    "spacing_mm": lb.spacing,
                    "force_n_per_mm": lb.force,
                }),
            );
        }
        obj.insert("extras".into(), extras);
        self.nodes[index] = Value::Object(obj);
        index
    }

    /// The mesh of `node`'s own primitives, or `None` when it has none to draw.
    fn mesh(&mut self, node: &Node, cache: &GltfCache, used: &mut EncodedMap) -> Option<usize> {
        let geometry: Vec<&Arc<Geometry>> =
            node.geometry.iter().filter(|g| !g.is_empty()).collect();
        if geometry.is_empty() {
            return None;
        }
        let material = self.material(&node.kind, node.color);
        let mut primitives = Vec::new();
        for g in geometry {
            let e = cache.encoded(g, used);
            let pos = self.vec3(&e.positions, e.vertex_count, Some((e.lo, e.hi)));
            match &**g {
                Geometry::Triangles { groups, .. } => {
                    let nrm = self.vec3(&e.normals, e.vertex_count, None);
                    let idx = self.indices(&e);
                    let mut primitive = json!({
                        "attributes": { "POSITION": pos, "NORMAL": nrm },
                        "indices": idx,
                        "material": material,
                        "mode": MODE_TRIANGLES,
                    });
                    if !groups.is_empty() {
                        let groups: Vec<Value> = groups
                            .iter()
                            .map(|g| json!({ "name": g.name, "triangles": g.runs() }))
                            .collect();
                        primitive["extras"] = json!({ "groups": groups });
                    }
                    primitives.push(primitive);
                }
                Geometry::LineStrip { .. } => {
                    primitives.push(json!({
                        "attributes": { "POSITION": pos },
                        "material": material,
                        "mode": MODE_LINE_STRIP,
                    }));
                }
            }
        }
        self.meshes
            .push(json!({ "name": node.name, "primitives": primitives }));
        Some(self.meshes.len() - 1)
    }

    /// The material of a kind (named by it, in the kind's colour), created on first use.
    fn material(&mut self, kind: &str, color: [f64; 3]) -> usize {
        if let Some(i) = self.material_kinds.iter().position(|k| k == kind) {
            return i;
        }
        let [r, g, b] = color;
        self.materials.push(json!({
            "name": kind,
            "pbrMetallicRoughness": {
                "baseColorFactor": [r, g, b, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.6,
            },
            "doubleSided": true,
        }));
        self.material_kinds.push(kind.to_string());
        self.materials.len() - 1
    }

    /// A `VEC3` float accessor of `count` vectors over `bytes`, with `min`/`max` when
    /// given.
    fn vec3(&mut self, bytes: &[u8], count: usize, bounds: Option<([f32; 3], [f32; 3])>) -> usize {
        let view = self.view_with(bytes.len(), ARRAY_BUFFER, |buffer| {
            buffer.extend_from_slice(bytes);
        });
        let mut acc = Map::new();
        acc.insert("bufferView".into(), json!(view));
        acc.insert("componentType".into(), json!(FLOAT));
        acc.insert("count".into(), json!(count));
        acc.insert("type".into(), json!("VEC3"));
        if let Some((lo, hi)) = bounds {
            let as_json = |a: [f32; 3]| json!(a.map(f64::from));
            acc.insert("min".into(), as_json(lo));
            acc.insert("max".into(), as_json(hi));
        }
        self.accessors.push(Value::Object(acc));
        self.accessors.len() - 1
    }

    /// The index accessor of an encoded tessellation.
    fn indices(&mut self, e: &Encoded) -> usize {
        let view = self.view_with(e.indices.len(), ELEMENT_ARRAY_BUFFER, |buffer| {
            buffer.extend_from_slice(&e.indices);
        });
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": if e.small_indices { UNSIGNED_SHORT } else { UNSIGNED_INT },
            "count": e.index_count,
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    /// Appends a buffer view of `len` bytes, starting on a 4-byte boundary, that `write`
    /// fills straight into the buffer (no intermediate copy).
    fn view_with(&mut self, len: usize, target: u32, write: impl FnOnce(&mut Vec<u8>)) -> usize {
        pad(&mut self.buffer, 0);
        let offset = self.buffer.len();
        self.buffer.reserve(len);
        write(&mut self.buffer);
        debug_assert_eq!(
            self.buffer.len() - offset,
            len,
            "the writer fills exactly its view"
        );
        self.views.push(json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": len,
            "target": target,
        }));
        self.views.len() - 1
    }

    /// The JSON document; `uri` is the buffer's data URI for `.gltf` (none in a GLB).
    fn json(&self, uri: Option<String>) -> Value {
        let mut root = Map::new();
        root.insert(
            "asset".into(),
            json!({
                "version": "2.0",
                "generator": format!("dieface {}", env!("CARGO_PKG_VERSION")),
            }),
        );
        let mut scene = Map::new();
        scene.insert("name".into(), json!(self.source));
        // The schema wants at least one node in a scene's list, so an empty scene has none.
        if !self.roots.is_empty() {
            scene.insert("nodes".into(), json!(self.roots));
        }
        root.insert("scene".into(), json!(0));
        root.insert("scenes".into(), json!([Value::Object(scene)]));
        let mut put = |key: &str, items: &[Value]| {
            if !items.is_empty() {
                root.insert(key.into(), Value::Array(items.to_vec()));
            }
        };
        put("nodes", &self.nodes);
        put("meshes", &self.meshes);
        put("materials", &self.materials);
        put("accessors", &self.accessors);
        put("bufferViews", &self.views);
        if !self.buffer.is_empty() {
            let mut buffer = Map::new();
            buffer.insert("byteLength".into(), json!(self.buffer.len()));
            if let Some(uri) = uri {
                buffer.insert("uri".into(), json!(uri));
            }
            root.insert("buffers".into(), json!([Value::Object(buffer)]));
        }
        Value::Object(root)
    }
}

/// Pads `bytes` with `fill` to a multiple of 4.
fn pad(bytes: &mut Vec<u8>, fill: u8) {
    while bytes.len() % 4 != 0 {
        bytes.push(fill);
    }
}

/// Standard base64 with padding (RFC 4648), for the `.gltf` data URI.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (input, expected) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(input.as_bytes()), expected);
        }
    }

    #[test]
    fn press_axes_map_to_gltf_y_up_metres() {
        assert_eq!(
            to_gltf_position(DVec3::new(1000.0, 2000.0, 3000.0)),
            [1.0, 3.0, -2.0]
        );
        assert_eq!(to_gltf_direction(DVec3::Z), [0.0, 1.0, 0.0]);
    }

    /// A scene of one curve node through `far`.
    fn scene_through(far: DVec3) -> Scene {
        Scene {
            nodes: vec![Node {
                name: "binder/front".into(),
                kind: "blankholder".into(),
                color: [0.5; 3],
                line: 7,
                children: Vec::new(),
                geometry: vec![Arc::new(Geometry::LineStrip {
                    points: vec![DVec3::ZERO, far],
                })],
                line_bead: None,
            }],
            tolerance_mm: 0.05,
            source_name: "x.die".into(),
        }
    }

    #[test]
    fn vertices_beyond_the_modelling_range_are_named_not_written_as_infinity() {
        assert_eq!(
            out_of_range(&scene_through(DVec3::new(1e6, -1e6, 5.0))),
            None
        );
        for bad in [1e40, 2e6, f64::INFINITY, f64::NAN] {
            let found = out_of_range(&scene_through(DVec3::new(0.0, bad, 0.0))).expect("refused");
            assert_eq!(found.part, "binder/front");
            assert_eq!(found.line, 7);
            assert!(found.coordinate.is_nan() || found.coordinate == bad);
        }
    }
}
