//! A built plate part's mid-surface as a mesh (its area and its solid's volume are
//! the mesh's own measures, `Mesh::total_area` and `Mesh::enclosed_volume`).

use glam::{DVec2, DVec3};

use super::super::geometry::{face_loops, mid_sides, newell, MidSurface};
use super::super::thicken::ThickenError;
use super::super::topology::{FaceId, Sheet, TopologyError};
use super::layout::Frame;
use crate::geom::mesh::{Face, Mesh};
use crate::geom::tessellate::triangulate_loops;

/// One side of each sheet (the one of lower id of a pair of twins), each face
/// triangulated in its plane, with each such side's area (mm²).
pub(super) fn mid_surface(
    sheet: &Sheet,
    mid: &MidSurface,
) -> Result<(Mesh, Vec<(FaceId, f64)>), ThickenError> {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut areas = Vec::new();
    for f in mid_sides(sheet)? {
        let loops = face_loops(sheet, mid, f)?;
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
        let mut area = 0.0;
        for [a, c, d] in triangulate_loops(&flat).map_err(|e| ThickenError::Triangulation(f, e))? {
            let [pa, pc, pd] = [a, c, d].map(|i| positions[first as usize + i]);
            area += 0.5 * (pc - pa).cross(pd - pa).length();
            faces.push(Face::triangle(
                first + a as u32,
                first + c as u32,
                first + d as u32,
            ));
        }
        areas.push((f, area));
    }
    let mesh = Mesh::new(positions, faces)
        .map_err(|e| ThickenError::Topology(TopologyError::Invalid(e.to_string())))?;
    Ok((mesh, areas))
}

/// A sheet of the part as the designer named it (`plate`, a flange, a lifted region, a
/// bend's turned part), with its area and its thickness.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetFigures {
    /// The name its faces carry before the first dot (`plate`, `lip`, `pad`, ...).
    pub name: String,
    /// Its mid-surface's area (mm²).
    pub area: f64,
    /// Its thickness (mm).
    pub thickness: f64,
}

/// The figures of each named sheet: the areas of its sides (`areas`, one side of each
/// pair of twins), summed by the name before the first dot of each side's face name,
/// with the side's thickness; by name.
pub(super) fn sheet_figures(
    areas: &[(FaceId, f64)],
    name: impl Fn(FaceId) -> String,
    thickness: impl Fn(FaceId) -> f64,
) -> Vec<SheetFigures> {
    let mut by_name: std::collections::BTreeMap<String, SheetFigures> = Default::default();
    for &(f, area) in areas {
        let full = name(f);
        let key = full.split('.').next().unwrap_or(&full).to_string();
        let entry = by_name.entry(key.clone()).or_insert(SheetFigures {
            name: key,
            area: 0.0,
            thickness: thickness(f),
        });
        entry.area += area;
    }
    by_name.into_values().collect()
}
