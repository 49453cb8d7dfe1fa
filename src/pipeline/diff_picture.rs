//! The picture `dieface diff --png` draws: the new version's geometry coloured by how
//! far each point lies from the old version's, with a scale in millimetres, so a
//! reviewer sees at a glance what an edit moved and by how much.

use crate::export::render::{distance_color, Legend, Linear, Paint, Picture, Polyline, Shaded};
use crate::export::scene::{Geometry, Node, Scene};
use crate::geom::mesh::distance::NearestTriangles;
use crate::geom::mesh::rounding::index::Triangle;

/// The curves' colour (linear RGB): a dark grey that no distance colour takes.
const CURVE_GREY: Linear = [0.05, 0.05, 0.05];

/// The least top of the colour scale (mm): an edit that moved nothing draws everything
/// at the scale's cold end rather than stretching rounding noise over the whole scale.
pub const LEAST_SCALE: f64 = 0.01;

/// The new scene's surfaces, each vertex coloured by its distance to the old scene
/// ([`distance_color`], from 0 to the largest distance found): a declaration's pieces
/// are measured against the old declaration of the same name, a declaration the old
/// version lacks against everything old. Curves are drawn in grey; the legend is the
/// colour scale in millimetres.
pub fn distance_picture(old: &Scene, new: &Scene) -> Picture {
    // The whole old scene, indexed only if a declaration is new.
    let mut everything: Option<NearestTriangles> = None;
    let mut coloured: Vec<(Shaded, Vec<f64>)> = Vec::new();
    let mut lines = Vec::new();
    let mut largest = 0.0f64;
    for top in &new.nodes {
        let own: Vec<Triangle> = old
            .nodes
            .iter()
            .find(|o| o.name == top.name)
            .map(triangles_of)
            .unwrap_or_default();
        let own = (!own.is_empty()).then(|| NearestTriangles::new(own));
        let against = match &own {
            Some(index) => index,
            None => everything.get_or_insert_with(|| {
                NearestTriangles::new(old.nodes.iter().flat_map(triangles_of).collect())
            }),
        };
        for node in top.walk() {
            for g in node.primitives() {
                match g {
                    Geometry::Triangles {
                        positions,
                        normals,
                        indices,
                        ..
                    } => {
                        let distances = against.distances(positions);
                        largest = distances
                            .iter()
                            .copied()
                            .filter(|d| d.is_finite())
                            .fold(largest, f64::max);
                        coloured.push((
                            Shaded {
                                positions: positions.clone(),
                                normals: normals.clone(),
                                indices: indices.clone(),
                                paint: Paint::Uniform(CURVE_GREY),
                            },
                            distances,
                        ));
                    }
                    Geometry::LineStrip { points } => lines.push(Polyline {
                        points: points.clone(),
                        color: CURVE_GREY,
                    }),
                }
            }
        }
    }
    let max = largest.max(LEAST_SCALE);
    let meshes = coloured
        .into_iter()
        .map(|(mut shaded, distances)| {
            // A point with nothing old to measure against is drawn grey (NaN).
            shaded.paint = Paint::PerVertex(
                distances
                    .iter()
                    .map(|&d| distance_color(if d.is_finite() { d } else { f64::NAN }, max))
                    .collect(),
            );
            shaded
        })
        .collect();
    Picture {
        meshes,
        lines,
        legend: Legend::Scale {
            title: "distance from old".into(),
            unit: "mm".into(),
            max,
        },
    }
}

/// Every triangle of a node and its children.
fn triangles_of(node: &Node) -> Vec<Triangle> {
    node.walk().into_iter().flat_map(Node::triangles).collect()
}
