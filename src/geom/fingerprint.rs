//! Content fingerprints of kernel geometry: a 64-bit hash of everything that defines a
//! curve, surface, trimmed surface or mesh (degrees, knots, control points and weights
//! as their exact bits).
//!
//! Caches key on them (the export's tessellation cache, the features' piece memo):
//! geometry rebuilt bit for bit after an edit hits the cache even though it is a new
//! object. A fingerprint only finds a candidate; the caches compare the geometry itself
//! before they reuse anything, so a collision costs a tessellation, never a wrong mesh.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

use glam::{DVec2, DVec3};

use super::curve::NurbsCurve;
use super::mesh::Mesh;
use super::surface::NurbsSurface;
use super::trimmed::TrimmedSurface;

/// Geometry that can be fingerprinted.
pub trait Fingerprint {
    /// Feeds everything that defines `self` to `h`.
    fn feed(&self, h: &mut DefaultHasher);

    /// The 64-bit fingerprint: equal geometry gives equal fingerprints, in every run
    /// (the hasher has fixed keys).
    fn fingerprint(&self) -> u64 {
        let mut h = DefaultHasher::new();
        self.feed(&mut h);
        h.finish()
    }
}

/// Coordinates as their bits, so `-0.0` and `0.0` differ as the tessellation would see.
trait Coords {
    fn coords(&self, out: &mut DefaultHasher);
}

impl Coords for DVec2 {
    fn coords(&self, h: &mut DefaultHasher) {
        self.x.to_bits().hash(h);
        self.y.to_bits().hash(h);
    }
}

impl Coords for DVec3 {
    fn coords(&self, h: &mut DefaultHasher) {
        self.x.to_bits().hash(h);
        self.y.to_bits().hash(h);
        self.z.to_bits().hash(h);
    }
}

fn floats(values: &[f64], h: &mut DefaultHasher) {
    values.len().hash(h);
    for v in values {
        v.to_bits().hash(h);
    }
}

fn points<P: Coords>(points: &[P], h: &mut DefaultHasher) {
    points.len().hash(h);
    for p in points {
        p.coords(h);
    }
}

fn weights(w: Option<&[f64]>, h: &mut DefaultHasher) {
    match w {
        Some(w) => floats(w, h),
        None => usize::MAX.hash(h),
    }
}

impl<P: Coords + crate::geom::point::Point> Fingerprint for NurbsCurve<P> {
    fn feed(&self, h: &mut DefaultHasher) {
        "curve".hash(h);
        self.degree().hash(h);
        floats(self.knots().as_slice(), h);
        points(self.control_points(), h);
        weights(self.weights(), h);
    }
}

impl Fingerprint for NurbsSurface {
    fn feed(&self, h: &mut DefaultHasher) {
        "surface".hash(h);
        (self.degree_u(), self.degree_v(), self.counts()).hash(h);
        floats(self.knots_u().as_slice(), h);
        floats(self.knots_v().as_slice(), h);
        points(self.control_points(), h);
        weights(self.weights(), h);
    }
}

impl Fingerprint for TrimmedSurface {
    fn feed(&self, h: &mut DefaultHasher) {
        "trimmed".hash(h);
        self.surface().feed(h);
        self.outer().curve().feed(h);
    }
}

impl Fingerprint for Mesh {
    fn feed(&self, h: &mut DefaultHasher) {
        "mesh".hash(h);
        points(self.positions(), h);
        self.faces().hash(h);
        match self.normals() {
            Some(n) => points(n, h),
            None => usize::MAX.hash(h),
        }
    }
}
