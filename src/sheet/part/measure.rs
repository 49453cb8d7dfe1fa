//! A built plate part's mid-surface as a mesh (its area and its solid's volume are
//! the mesh's own measures, `Mesh::total_area` and `Mesh::enclosed_volume`).

use glam::{DVec2, DVec3};

use super::super::geometry::{newell, MidSurface};
use super::super::thicken::ThickenError;
use super::super::topology::{FaceRole, Sheet, TopologyError};
use super::layout::Frame;
use crate::geom::mesh::{Face, Mesh};
use crate::geom::tessellate::triangulate_loops;

/// One side of each sheet (the one of lower id of a pair of twins), each face
/// triangulated in its plane.
pub(super) fn mid_surface(sheet: &Sheet, mid: &MidSurface) -> Result<Mesh, ThickenError> {
    let b = &sheet.brep;
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for f in b.faces() {
        let FaceRole::Side { twin } = sheet.face_role(f)? else {
            continue;
        };
        if twin < f {
            continue;
        }
        let loops: Vec<Vec<DVec3>> = b
            .loops_of(f)?
            .iter()
            .map(|&l| {
                b.loop_halves(l)?
                    .into_iter()
                    .map(|h| {
                        let v = b.vertex(h)?;
                        mid.point(v)
                            .ok_or_else(|| TopologyError::Dead(format!("point of vertex {}", v.0)))
                    })
                    .collect::<Result<Vec<DVec3>, TopologyError>>()
            })
            .collect::<Result<_, _>>()?;
        let normal = newell(&loops[0]).normalize_or_zero();
        if normal == DVec3::ZERO {
            return Err(ThickenError::Degenerate(f));
        }
        let frame = Frame::new(loops[0][0], normal);
        let flat: Vec<Vec<DVec2>> = loops
            .iter()
            .map(|ring| ring.iter().map(|&p| frame.flat(p)).collect())
            .collect();
        let first = positions.len() as u32;
        positions.extend(loops.iter().flatten().copied());
        for [a, c, d] in triangulate_loops(&flat).map_err(|e| ThickenError::Triangulation(f, e))? {
            faces.push(Face::triangle(
                first + a as u32,
                first + c as u32,
                first + d as u32,
            ));
        }
    }
    Mesh::new(positions, faces)
        .map_err(|e| ThickenError::Topology(TopologyError::Invalid(e.to_string())))
}
