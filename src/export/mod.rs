//! Export: the die model to files a viewer, a mesher or CAD/CAM reads.
//!
//! Export reads [`crate::die::model::DieModel`], never a language value. For the mesh
//! formats it is two steps: [`build_scene`] tessellates every part of the model into a
//! [`Scene`] of named [`Node`]s (press coordinates, millimetres, one node per
//! declaration, children for the pieces of lists and feature blocks; `scene::SceneCache`
//! keeps tessellations between builds), and [`encode`] writes the scene in a
//! [`Format`]:
//!
//! * glTF 2.0 (`.glb` binary, `.gltf` JSON with the buffer embedded as a data URI): metres
//!   and +Y up as the glTF spec requires, so press `(x, y, z)` mm becomes glTF
//!   `(x, z, -y) / 1000` (a proper rotation: windings and normals stay right-handed);
//!   see [`gltf`].
//! * Wavefront OBJ: millimetres in press coordinates (OBJ has no unit or axis
//!   convention), one group per node; see [`obj`].
//!
//! STEP ([`step`]) writes the exact B-spline faces of the model's die face, sewn into
//! shells (the build pipeline's `step_bytes` calls it).
//!
//! [`fe`] writes shell-element decks of a meshed die face for forming simulation
//! (LS-DYNA keyword, Nastran bulk data) from plain nodes and shells.
//!
//! [`seams`] measures the normal jump where one piece's open edge lies on another's
//! (the viewer's seam analysis).
//!
//! [`render`] draws the scene as a shaded picture (PNG) with a software rasterizer:
//! `dieface render`.
//!
//! Every encoder is deterministic: the same scene gives the same bytes (no hash-map
//! order, stable float formatting, little-endian buffers). [`atomic::write_atomic`]
//! writes a file through a temporary sibling and a rename, so a failed build never
//! leaves a half-written or missing output behind.

pub mod atomic;
pub mod fe;
pub mod gltf;
pub mod obj;
pub mod render;
pub mod scene;
pub mod seams;
pub mod step;

use std::path::Path;

pub use scene::{build_scene, Geometry, LineBead, Node, Scene};

/// Output formats by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Binary glTF 2.0 (`.glb`).
    Glb,
    /// JSON glTF 2.0 with the buffer embedded as a base64 data URI (`.gltf`).
    Gltf,
    /// Wavefront OBJ (`.obj`), millimetres, press coordinates.
    Obj,
}

impl Format {
    /// The format named by `p`'s extension (case-insensitive), or `None` for any other.
    pub fn from_path(p: &Path) -> Option<Format> {
        let ext = p.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "glb" => Some(Format::Glb),
            "gltf" => Some(Format::Gltf),
            "obj" => Some(Format::Obj),
            _ => None,
        }
    }

    /// The extension the format is written with (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Glb => "glb",
            Format::Gltf => "gltf",
            Format::Obj => "obj",
        }
    }
}

/// Encodes a scene in a format (deterministic bytes).
pub fn encode(scene: &Scene, format: Format) -> Vec<u8> {
    encode_with(scene, format, &mut gltf::GltfCache::default())
}

/// [`encode`], with glTF buffer bytes of unchanged tessellations from `cache` (the
/// same bytes, converted once).
pub fn encode_with(scene: &Scene, format: Format, cache: &mut gltf::GltfCache) -> Vec<u8> {
    match format {
        Format::Glb => gltf::encode_glb_with(scene, cache),
        Format::Gltf => gltf::encode_gltf_with(scene, cache),
        Format::Obj => obj::encode_obj(scene),
    }
}
