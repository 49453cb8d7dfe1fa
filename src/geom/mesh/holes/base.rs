//! The base surface a hole is filled from (paper 002, section 3): an initial grid on
//! the hole's projection plane covering the loop with a margin, each node projected
//! along the plane's normal onto the mesh round the hole (its height there, where it
//! meets a face), the thin plate through those heights (`thin_plate`), and the bicubic
//! Ferguson patches through the plate's nodes (`ferguson`). A loop whose nodes and
//! first ring of faces lie in one plane gets that plane directly (eq. 5).

use glam::{DVec2, DVec3};

use super::ferguson::FergusonPatches;
use super::plane::ProjectionPlane;
use super::thin_plate::{solve_plate, HeightGrid, PlateError};
use crate::geom::inversion::{project_by_newton, SurfaceEval, SurfacePoint};
use crate::geom::mesh::stars::VertexStars;
use crate::geom::mesh::{Face, Mesh, VertexId};
use crate::geom::surface::NurbsSurface;

/// The fewest and the most grid cells across a hole's longest spread.
const CELLS_ACROSS: (usize, usize) = (8, 24);

/// Grid cells of margin round the loop's box: two rings of nodes on the mesh fix the
/// plate's position and slope at the loop, and a third keeps the grid's free edge
/// away from them.
const MARGIN_CELLS: usize = 3;

/// The least cosine between a face the flood reads and the plane's normal: a face
/// turned more than 85 deg from the plane is not read (it stands on edge to the plane,
/// or faces away, as a flange folded under does).
const FLOOD_FACING: f64 = 0.087;

/// How far (a share of the loop's span) the loop's nodes and ring may lie off one
/// plane for the hole to be taken as planar.
const PLANAR: f64 = 1e-9;

/// A hole's base surface and the grid it was made on.
#[derive(Debug, Clone)]
pub struct BaseSurface {
    /// The projection plane.
    pub plane: ProjectionPlane,
    /// The grid's first node, in the plane's coordinates: the surface's `(u, v)` is
    /// the plane position less this.
    pub corner: DVec2,
    /// The grid's step (mm), the same along both axes.
    pub step: f64,
    /// The surface as the fill evaluates it, parametrised by plane position less
    /// `corner`.
    pub form: BaseForm,
    /// Whether the loop was planar and the plane taken directly.
    pub planar: bool,
    /// How many grid nodes lay on the mesh (known) and how many the plate found.
    pub known_nodes: usize,
    pub solved_nodes: usize,
}

/// What a base surface is made of.
#[derive(Debug, Clone)]
pub enum BaseForm {
    /// A B-spline surface of the kernel, evaluated as it is: a planar loop's plane, a
    /// bilinear surface over the grid.
    Bspline(NurbsSurface),
    /// Ferguson patches over the grid's nodes (eq. 2), evaluated from their Hermite
    /// data: the fill projects onto them and maps back through them.
    Patches(FergusonPatches),
}

impl BaseSurface {
    /// The surface parameters straight above (along the plane's normal) `p`.
    pub fn uv_above(&self, p: DVec3) -> DVec2 {
        self.plane.to_plane(p).0 - self.corner
    }

    /// The point of the base surface at `(u, v)`.
    pub fn point_at(&self, uv: DVec2) -> DVec3 {
        self.evaluated().point_at(uv.x, uv.y)
    }

    /// The foot of `p` on the base surface by Newton-Raphson from `(u, v)` `guess`
    /// (eq. 7-9; the kernel's iteration), or `None` where it does not converge.
    pub fn foot(&self, p: DVec3, guess: DVec2) -> Option<SurfacePoint> {
        project_by_newton(self.evaluated(), p, (guess.x, guess.y))
    }

    /// The base surface as a B-spline surface of the kernel (the Ferguson patches'
    /// Bézier nets joined, or the plane): what the `fill` block exports and the rest of
    /// the kernel reads. Made when asked for; the fill itself never needs it.
    pub fn surface(&self) -> NurbsSurface {
        match &self.form {
            BaseForm::Bspline(surface) => surface.clone(),
            BaseForm::Patches(patches) => patches.surface(),
        }
    }

    /// The surface as it is evaluated.
    fn evaluated(&self) -> &dyn SurfaceEval {
        match &self.form {
            BaseForm::Bspline(surface) => surface,
            BaseForm::Patches(patches) => patches,
        }
    }
}

/// Why a base surface could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaseError {
    #[error(transparent)]
    Plate(#[from] PlateError),
    #[error("the base surface could not be made: {0}")]
    Surface(String),
}

/// The grid a base surface is made on: `nx` by `ny` cells of `step` from `corner`, in
/// the projection plane's coordinates.
struct Grid {
    corner: DVec2,
    step: f64,
    nx: usize,
    ny: usize,
}

impl Grid {
    /// Sets the height of every node of the grid that lies over the triangle `tri`
    /// (plane position and height at each corner) and has none yet: the first face
    /// read gives a node on a shared edge its height.
    fn sample(&self, tri: [(DVec2, f64); 3], known: &mut [Option<f64>]) {
        let (corner, step, nx, ny) = (self.corner, self.step, self.nx, self.ny);
        let (tlo, thi) = tri.iter().fold(
            (DVec2::INFINITY, DVec2::NEG_INFINITY),
            |(lo, hi), (q, _)| (lo.min(*q), hi.max(*q)),
        );
        let i0 = (((tlo.x - corner.x) / step).ceil().max(0.0)) as usize;
        let j0 = (((tlo.y - corner.y) / step).ceil().max(0.0)) as usize;
        let i1 = (((thi.x - corner.x) / step).floor()).min(nx as f64);
        let j1 = (((thi.y - corner.y) / step).floor()).min(ny as f64);
        if i1 < 0.0 || j1 < 0.0 {
            return;
        }
        let (a, b, c) = (tri[0].0, tri[1].0, tri[2].0);
        let area = (b - a).perp_dot(c - a);
        if area.abs() <= f64::MIN_POSITIVE {
            return;
        }
        for j in j0..=j1 as usize {
            for i in i0..=i1 as usize {
                let q = corner + DVec2::new(i as f64, j as f64) * step;
                let wa = (b - q).perp_dot(c - q) / area;
                let wb = (c - q).perp_dot(a - q) / area;
                let wc = 1.0 - wa - wb;
                let eps = -1e-12;
                if wa >= eps && wb >= eps && wc >= eps {
                    let k = j * (nx + 1) + i;
                    known[k].get_or_insert(wa * tri[0].1 + wb * tri[1].1 + wc * tri[2].1);
                }
            }
        }
    }
}

/// The flood's marks, over a mesh's faces and nodes: which the flood round one hole
/// has come to. Kept from hole to hole (the holes one thread fills) and cleared
/// entry by entry, so a hole costs what its own flood touches, not the whole mesh.
#[derive(Debug, Clone, Default)]
pub struct FloodScratch {
    faces: Marks,
    nodes: Marks,
}

/// Marks over the indices `0..len`, with the list of those set.
#[derive(Debug, Clone, Default)]
struct Marks {
    seen: Vec<bool>,
    set: Vec<u32>,
}

impl Marks {
    fn new(len: usize) -> Marks {
        Marks {
            seen: vec![false; len],
            set: Vec::new(),
        }
    }

    /// Whether `i` is marked for the first time (marking it). `i` is below the length
    /// the marks were made for: the flood's faces and nodes are the mesh's own.
    fn first(&mut self, i: u32) -> bool {
        let seen = &mut self.seen[i as usize];
        let first = !*seen;
        if first {
            *seen = true;
            self.set.push(i);
        }
        first
    }

    /// Every mark unset again, the ones set since the last clear only.
    fn clear(&mut self) {
        for i in self.set.drain(..) {
            self.seen[i as usize] = false;
        }
    }
}

impl FloodScratch {
    /// Marks for the faces and nodes of `mesh`, none set.
    pub fn new(mesh: &Mesh) -> FloodScratch {
        FloodScratch {
            faces: Marks::new(mesh.face_count()),
            nodes: Marks::new(mesh.vertex_count()),
        }
    }

    fn clear(&mut self) {
        self.faces.clear();
        self.nodes.clear();
    }
}

/// Each grid node's height where it meets a face round the hole, straight along the
/// plane's normal (`None` where it meets none: over the hole, or off the panel).
///
/// The faces read are found from the faces at the loop's nodes, flooded across their
/// nodes (to every face at a node of a face taken) while a face faces the plane (its
/// normal within 85 deg of the plane's) and lies over the grid's box. A face far off in
/// the mesh that only overlaps the box in projection (a flange folded under) is never
/// reached. Faces are read in the order the flood reaches them, so every build gives a
/// node on a shared edge the same face's height.
fn heights_round(
    stars: &VertexStars,
    loop_nodes: &[VertexId],
    plane: &ProjectionPlane,
    grid: &Grid,
    scratch: &mut FloodScratch,
) -> Vec<Option<f64>> {
    let mesh = stars.mesh();
    let (lo, hi) = (
        grid.corner,
        grid.corner + DVec2::new(grid.nx as f64, grid.ny as f64) * grid.step,
    );
    let mut known: Vec<Option<f64>> = vec![None; (grid.nx + 1) * (grid.ny + 1)];
    // A face's corners on the plane, if it faces the plane (its normal within 85 deg
    // of the plane's) and lies over the box. The normal is read in the plane's own
    // frame (right-handed, so a cross product there is the normal's components along
    // e1, e2 and the plane's normal), from the corners as they are projected anyway.
    let over = |face: &Face| -> Option<[(DVec2, f64); 4]> {
        let mut corners = [(DVec2::ZERO, 0.0); 4];
        let (mut flo, mut fhi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        for (slot, &v) in corners.iter_mut().zip(face.indices()) {
            // Mesh::new checked every face index against the positions.
            *slot = plane.to_plane(mesh.positions()[v as usize]);
            flo = flo.min(slot.0);
            fhi = fhi.max(slot.0);
        }
        if !(flo.cmple(hi).all() && fhi.cmpge(lo).all()) {
            return None;
        }
        let at = |k: usize| DVec3::new(corners[k].0.x, corners[k].0.y, corners[k].1);
        let doubled_area = if face.is_quad() {
            (at(2) - at(0)).cross(at(3) - at(1))
        } else {
            (at(1) - at(0)).cross(at(2) - at(0))
        };
        (doubled_area.z > FLOOD_FACING * doubled_area.length()).then_some(corners)
    };
    // Each face judged once, however many of its nodes the flood comes to it from;
    // each node flooded from once.
    scratch.clear();
    let mut nodes: Vec<VertexId> = Vec::new();
    for &v in loop_nodes {
        if v.index() < mesh.vertex_count() && scratch.nodes.first(v.0) {
            nodes.push(v);
        }
    }
    while let Some(v) = nodes.pop() {
        for &f in stars.faces(v) {
            if !scratch.faces.first(f.0) {
                continue;
            }
            // The stars list only the mesh's own faces.
            let face = mesh.faces()[f.index()];
            let Some(corners) = over(&face) else {
                continue;
            };
            // A quad is read as its two triangles.
            for k in 1..face.vertex_count() - 1 {
                grid.sample([corners[0], corners[k], corners[k + 1]], &mut known);
            }
            for &w in face.indices() {
                if scratch.nodes.first(w) {
                    nodes.push(VertexId(w));
                }
            }
        }
    }
    known
}

/// The base surface of the hole whose loop runs through `loop_nodes` (in order), on
/// `plane`, its interior sized for elements about `size` long.
pub fn base_surface(
    stars: &VertexStars,
    loop_nodes: &[VertexId],
    plane: &ProjectionPlane,
    size: f64,
) -> Result<BaseSurface, BaseError> {
    let mut scratch = FloodScratch::new(stars.mesh());
    base_surface_with(stars, loop_nodes, plane, size, &mut scratch)
}

/// [`base_surface`] with the flood's marks handed in: the holes one thread fills share
/// one set of marks instead of each clearing tables the size of the mesh.
pub fn base_surface_with(
    stars: &VertexStars,
    loop_nodes: &[VertexId],
    plane: &ProjectionPlane,
    size: f64,
    scratch: &mut FloodScratch,
) -> Result<BaseSurface, BaseError> {
    let mesh = stars.mesh();
    let flat: Vec<(DVec2, f64)> = loop_nodes
        .iter()
        .map(|&v| plane.to_plane(mesh.positions()[v.index()]))
        .collect();
    let (lo, hi) = flat.iter().fold(
        (DVec2::INFINITY, DVec2::NEG_INFINITY),
        |(lo, hi), (q, _)| (lo.min(*q), hi.max(*q)),
    );
    let span = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let cells = ((span / size.max(f64::MIN_POSITIVE)).ceil() as usize)
        .clamp(CELLS_ACROSS.0, CELLS_ACROSS.1);
    let step = span / cells as f64;
    let corner = lo - DVec2::splat(MARGIN_CELLS as f64 * step);
    let far = hi + DVec2::splat(MARGIN_CELLS as f64 * step);
    let nx = ((far.x - corner.x) / step).ceil() as usize;
    let ny = ((far.y - corner.y) / step).ceil() as usize;

    // Planar: the loop and the faces at its nodes all on the plane (a node of several
    // of those faces is read once for each).
    let planar = loop_nodes
        .iter()
        .flat_map(|&v| stars.faces(v))
        .flat_map(|&f| mesh.faces()[f.index()].indices())
        .all(|&v| plane.to_plane(mesh.positions()[v as usize]).1.abs() <= PLANAR * span);
    if planar {
        let corners = |i: f64, j: f64| plane.from_plane(corner + DVec2::new(i, j), 0.0);
        let (w, h) = (nx as f64 * step, ny as f64 * step);
        let surface = NurbsSurface::new(
            1,
            1,
            vec![0.0, 0.0, w, w],
            vec![0.0, 0.0, h, h],
            vec![
                vec![corners(0.0, 0.0), corners(0.0, h)],
                vec![corners(w, 0.0), corners(w, h)],
            ],
        )
        .map_err(|e| BaseError::Surface(e.to_string()))?;
        return Ok(BaseSurface {
            plane: *plane,
            corner,
            step,
            form: BaseForm::Bspline(surface),
            planar: true,
            known_nodes: 0,
            solved_nodes: 0,
        });
    }
    let grid = Grid {
        corner,
        step,
        nx,
        ny,
    };
    let known = heights_round(stars, loop_nodes, plane, &grid, scratch);
    let known_nodes = known.iter().filter(|h| h.is_some()).count();
    let grid = HeightGrid { nx, ny, known };
    let heights = solve_plate(&grid)?;
    // The grid's points, node (i, j) at i * (ny + 1) + j (i along u).
    let points: Vec<DVec3> = (0..=nx)
        .flat_map(|i| (0..=ny).map(move |j| (i, j)))
        .map(|(i, j)| {
            let q = corner + DVec2::new(i as f64, j as f64) * step;
            plane.from_plane(q, heights[j * (nx + 1) + i])
        })
        .collect();
    let patches = FergusonPatches::new(points, nx + 1, ny + 1, step)
        .map_err(|e| BaseError::Surface(e.to_string()))?;
    Ok(BaseSurface {
        plane: *plane,
        corner,
        step,
        form: BaseForm::Patches(patches),
        planar: false,
        known_nodes,
        solved_nodes: (nx + 1) * (ny + 1) - known_nodes,
    })
}
