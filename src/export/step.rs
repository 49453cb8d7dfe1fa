//! STEP (ISO 10303-21, AP214 `AUTOMOTIVE_DESIGN`) of sewn B-spline faces.
//!
//! What CAD/CAM for die machining reads: every face an `ADVANCED_FACE` on a
//! `B_SPLINE_SURFACE_WITH_KNOTS` (a complex `RATIONAL_B_SPLINE_SURFACE` entity when it
//! carries weights), bounded by one `EDGE_LOOP` of `ORIENTED_EDGE`s over shared
//! `EDGE_CURVE`s (`B_SPLINE_CURVE_WITH_KNOTS`), the faces of each [`Shell`] in one
//! `OPEN_SHELL`, all shells in one `SHELL_BASED_SURFACE_MODEL` of a
//! `MANIFOLD_SURFACE_SHAPE_REPRESENTATION`, with the product and shape-definition
//! entities a reader expects. Millimetres; the length uncertainty is the sewing
//! tolerance.
//!
//! The output is deterministic: entities are numbered in the order they are written,
//! floats print in Rust's shortest round-trip form, and the header's time stamp is a
//! fixed date (the same script gives the same bytes).
//!
//! The `truck-stepio` crate writes STEP from truck's own topology types; using it would
//! mean converting every surface and edge into truck's kernel for the dozen entities
//! written here, so they are written directly.

use std::fmt::Write as _;

use crate::geom::sew::Shell;
use crate::geom::{Curve3, NurbsSurface};

/// The fixed time stamp of the header (a changing one would break byte-identical
/// output).
pub const TIME_STAMP: &str = "2000-01-01T00:00:00";

/// What the STEP file describes.
#[derive(Debug, Clone, PartialEq)]
pub struct StepModel<'a> {
    /// The product's name (the script's stem: `fender`).
    pub name: String,
    /// The shells, each with its name (`die_face`, `beads`).
    pub shells: Vec<(String, &'a Shell)>,
    /// The length uncertainty (mm) written to the context: the sewing tolerance.
    pub uncertainty: f64,
}

/// The STEP file's bytes.
pub fn encode_step(model: &StepModel) -> Vec<u8> {
    let mut w = Writer::default();
    let name = escape(&model.name);
    // Product structure.
    let app =
        w.add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')".into());
    w.add(format!(
        "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,{app})"
    ));
    let pctx = w.add(format!("PRODUCT_CONTEXT('',{app},'mechanical')"));
    let product = w.add(format!("PRODUCT('{name}','{name}','die face',({pctx}))"));
    w.add(format!(
        "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,({product}))"
    ));
    let formation = w.add(format!("PRODUCT_DEFINITION_FORMATION('','',{product})"));
    let dctx = w.add(format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',{app},'design')"
    ));
    let definition = w.add(format!(
        "PRODUCT_DEFINITION('design','',{formation},{dctx})"
    ));
    let shape = w.add(format!("PRODUCT_DEFINITION_SHAPE('','',{definition})"));
    // Units and context.
    let mm = w.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))".into());
    let rad = w.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))".into());
    let sr = w.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())".into());
    let unc = w.add(format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),{mm},'distance_accuracy_value','sewing tolerance')",
        real(model.uncertainty)
    ));
    let gctx = w.add(format!(
        "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT(({unc}))GLOBAL_UNIT_ASSIGNED_CONTEXT(({mm},{rad},{sr}))REPRESENTATION_CONTEXT('press coordinates','3D'))"
    ));
    // Geometry and topology.
    let origin = w.add("CARTESIAN_POINT('',(0.,0.,0.))".into());
    let z = w.add("DIRECTION('',(0.,0.,1.))".into());
    let x = w.add("DIRECTION('',(1.,0.,0.))".into());
    let placement = w.add(format!("AXIS2_PLACEMENT_3D('',{origin},{z},{x})"));
    let mut shells = Vec::new();
    for (shell_name, shell) in &model.shells {
        shells.push(w.shell(shell_name, shell));
    }
    let model_id = w.add(format!(
        "SHELL_BASED_SURFACE_MODEL('{name}',({}))",
        shells.join(",")
    ));
    let rep = w.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('{name}',({placement},{model_id}),{gctx})"
    ));
    w.add(format!("SHAPE_DEFINITION_REPRESENTATION({shape},{rep})"));

    let mut out = String::new();
    out.push_str("ISO-10303-21;\nHEADER;\n");
    out.push_str("FILE_DESCRIPTION(('dieface die face'),'2;1');\n");
    let _ = writeln!(
        out,
        "FILE_NAME('{name}.step','{TIME_STAMP}',(''),(''),'dieface {}','dieface','');",
        env!("CARGO_PKG_VERSION")
    );
    out.push_str("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\n");
    out.push_str("ENDSEC;\nDATA;\n");
    for (i, e) in w.entities.iter().enumerate() {
        let _ = writeln!(out, "#{}={e};", i + 1);
    }
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    out.into_bytes()
}

/// Entities in the order written; `#n` is the n-th (1-based).
#[derive(Default)]
struct Writer {
    entities: Vec<String>,
}

impl Writer {
    /// Adds an entity and returns its reference (`#n`).
    fn add(&mut self, entity: String) -> String {
        self.entities.push(entity);
        format!("#{}", self.entities.len())
    }

    fn point(&mut self, p: glam::DVec3) -> String {
        self.add(format!(
            "CARTESIAN_POINT('',({},{},{}))",
            real(p.x),
            real(p.y),
            real(p.z)
        ))
    }

    /// An `OPEN_SHELL` of the shell's faces.
    fn shell(&mut self, name: &str, shell: &Shell) -> String {
        let vertices: Vec<String> = shell
            .vertices
            .iter()
            .map(|&p| {
                let pt = self.point(p);
                self.add(format!("VERTEX_POINT('',{pt})"))
            })
            .collect();
        let edges: Vec<String> = shell
            .edges
            .iter()
            .map(|e| {
                let curve = self.curve(&e.curve);
                self.add(format!(
                    "EDGE_CURVE('',{},{},{curve},.T.)",
                    vertices[e.start], vertices[e.end]
                ))
            })
            .collect();
        let mut faces = Vec::new();
        for f in &shell.faces {
            // The outer loop, then a plain bound per hole (a bead imprinted on it).
            let mut bounds = Vec::with_capacity(1 + f.holes.len());
            for (k, l) in std::iter::once(&f.bound).chain(&f.holes).enumerate() {
                let oriented: Vec<String> = l
                    .iter()
                    .map(|&(e, forward)| {
                        self.add(format!(
                            "ORIENTED_EDGE('',*,*,{},{})",
                            edges[e],
                            flag(forward)
                        ))
                    })
                    .collect();
                let lp = self.add(format!("EDGE_LOOP('',({}))", oriented.join(",")));
                let keyword = if k == 0 {
                    "FACE_OUTER_BOUND"
                } else {
                    "FACE_BOUND"
                };
                bounds.push(self.add(format!("{keyword}('',{lp},.T.)")));
            }
            let surface = self.surface(f.face.surface());
            faces.push(self.add(format!(
                "ADVANCED_FACE('{}',({}),{surface},{})",
                escape(&f.face.name),
                bounds.join(","),
                flag(!f.reversed)
            )));
        }
        self.add(format!(
            "OPEN_SHELL('{}',({}))",
            escape(name),
            faces.join(",")
        ))
    }

    fn curve(&mut self, c: &Curve3) -> String {
        let points: Vec<String> = c.control_points().iter().map(|&p| self.point(p)).collect();
        let (mults, knots) = knot_lists(c.knots().as_slice());
        let closed = flag(c.start_point() == c.end_point());
        match c.weights() {
            None => self.add(format!(
                "B_SPLINE_CURVE_WITH_KNOTS('',{},({}),.UNSPECIFIED.,{closed},.F.,({mults}),({knots}),.UNSPECIFIED.)",
                c.degree(),
                points.join(",")
            )),
            Some(w) => self.add(format!(
                "(BOUNDED_CURVE()B_SPLINE_CURVE({},({}),.UNSPECIFIED.,{closed},.F.)B_SPLINE_CURVE_WITH_KNOTS(({mults}),({knots}),.UNSPECIFIED.)CURVE()GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE(({}))REPRESENTATION_ITEM(''))",
                c.degree(),
                points.join(","),
                reals(w)
            )),
        }
    }

    fn surface(&mut self, s: &NurbsSurface) -> String {
        let (nu, nv) = s.counts();
        let mut rows = Vec::with_capacity(nu);
        for i in 0..nu {
            let row: Vec<String> = (0..nv).map(|j| self.point(s.control_point(i, j))).collect();
            rows.push(format!("({})", row.join(",")));
        }
        let (mu, ku) = knot_lists(s.knots_u().as_slice());
        let (mv, kv) = knot_lists(s.knots_v().as_slice());
        let net = rows.join(",");
        let (du, dv) = (s.degree_u(), s.degree_v());
        match s.weights() {
            None => self.add(format!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',{du},{dv},({net}),.UNSPECIFIED.,.F.,.F.,.F.,({mu}),({mv}),({ku}),({kv}),.UNSPECIFIED.)"
            )),
            Some(w) => {
                let weights: Vec<String> = w.chunks(nv).map(|r| format!("({})", reals(r))).collect();
                self.add(format!(
                    "(BOUNDED_SURFACE()B_SPLINE_SURFACE({du},{dv},({net}),.UNSPECIFIED.,.F.,.F.,.F.)B_SPLINE_SURFACE_WITH_KNOTS(({mu}),({mv}),({ku}),({kv}),.UNSPECIFIED.)GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE(({}))REPRESENTATION_ITEM('')SURFACE())",
                    weights.join(",")
                ))
            }
        }
    }
}

/// A full knot vector as STEP's multiplicities and distinct knots.
fn knot_lists(knots: &[f64]) -> (String, String) {
    let mut mults: Vec<usize> = Vec::new();
    let mut distinct: Vec<f64> = Vec::new();
    for &k in knots {
        if distinct.last() == Some(&k) {
            if let Some(m) = mults.last_mut() {
                *m += 1;
            }
        } else {
            distinct.push(k);
            mults.push(1);
        }
    }
    let m: Vec<String> = mults.iter().map(|m| m.to_string()).collect();
    (m.join(","), reals(&distinct))
}

fn reals(v: &[f64]) -> String {
    v.iter().map(|&x| real(x)).collect::<Vec<_>>().join(",")
}

/// A STEP real: Rust's shortest round-trip digits, with the decimal point STEP needs
/// (`1.`, `1.5E-7`).
pub fn real(x: f64) -> String {
    let x = if x == 0.0 { 0.0 } else { x }; // no "-0."
    let s = format!("{x:?}");
    let (mantissa, exponent) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), Some(e.to_string())),
        None => (s, None),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').to_string()
    } else {
        format!("{mantissa}.")
    };
    match exponent {
        Some(e) => format!("{mantissa}E{e}"),
        None => mantissa,
    }
}

fn flag(b: bool) -> &'static str {
    if b {
        ".T."
    } else {
        ".F."
    }
}

/// A name as a STEP string: quotes doubled, non-ASCII replaced.
fn escape(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii() && c != '\\' { c } else { '_' })
        .collect::<String>()
        .replace('\'', "''")
}
