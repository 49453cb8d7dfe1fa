//! Random scripts written from the grammar (`grammar/die.pest`) and the signatures the
//! interpreter declares: every builtin's parameters and every feature kind's fields are
//! read from the library, so a new builtin or feature is fuzzed without touching this
//! file.
//!
//! Values are plausible (a length in mm, a point in the top view) or implausible (zero,
//! negative, huge, tiny, the wrong unit, the wrong type) at random, so a generated
//! script reaches the kernel as often as it reaches a diagnostic. One script in fifty
//! is a whole small die (product, opening, binder, step draw, beads) with random numbers,
//! so the features' kernels are exercised, not only the evaluator.

use std::fmt::Write;

use dieface::eval::builtins;
use dieface::eval::features::Registry;

use crate::rng::Rng;

/// What a generated script may call and declare, read from the interpreter.
pub struct Signatures {
    /// Each builtin: its name and parameters (name, required).
    builtins: Vec<(&'static str, Vec<(&'static str, bool)>)>,
    /// Each feature kind: its keyword, one-word fields and named-field words.
    features: Vec<(&'static str, Vec<&'static str>, Vec<&'static str>)>,
}

impl Signatures {
    /// The signatures of the standard builtins and feature kinds.
    pub fn standard() -> Signatures {
        let builtins = builtins::names()
            .filter_map(builtins::lookup)
            .map(|b| {
                let params = b.params.iter().map(|p| (p.name, p.required)).collect();
                (b.name, params)
            })
            .collect();
        let registry = Registry::standard();
        let features = registry
            .names()
            .filter_map(|n| registry.get(n))
            .map(|k| {
                let f = k.fields();
                (k.name(), f.single, f.named)
            })
            .collect();
        Signatures { builtins, features }
    }
}

/// Units a number may carry (and a few it may not).
const UNITS: &[&str] = &[
    "", "", " mm", "mm", " cm", " m", " in", " deg", " rad", " %",
];

/// Numbers worth trying: ordinary ones, edges of the range, and counts.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "10",
    "0.5",
    "12.5",
    "100",
    "1000",
    "0.001",
    "1e-9",
    "1e-300",
    "1e300",
    "1e308",
    "1e-400",
    "1e400",
    "65536",
    "1000000",
    "4294967296",
    "9007199254740993",
];

/// Views a sketch may be drawn in (and one that is not a view).
const VIEWS: &[&str] = &["top", "side_xz", "side_yz", "profile", "front", "\"top\""];

/// Standard-library modules (and one that does not exist).
const MODULES: &[&str] = &[
    "std/addendum",
    "std/beads",
    "std/sketch",
    "std/units",
    "std/none",
];

/// A generated script.
pub fn script(rng: &mut Rng, sig: &Signatures) -> String {
    if rng.chance(0.02) {
        return small_die(rng);
    }
    let mut g = Gen {
        rng,
        sig,
        names: Vec::new(),
        fns: Vec::new(),
        out: String::new(),
        budget: 400,
    };
    g.items();
    g.out
}

/// The writer of one script: the names declared so far (for references) and a budget
/// of expression nodes, so scripts stay small.
struct Gen<'a> {
    rng: &'a mut Rng,
    sig: &'a Signatures,
    names: Vec<String>,
    fns: Vec<(String, usize)>,
    out: String,
    budget: usize,
}

impl Gen<'_> {
    fn items(&mut self) {
        if self.rng.chance(0.3) {
            let _ = writeln!(self.out, "units mm deg");
        }
        for (i, m) in MODULES.iter().enumerate() {
            if self.rng.chance(0.15) {
                let _ = writeln!(self.out, "import \"{m}\" as m{i}");
                self.names.push(format!("m{i}"));
            }
        }
        let count = self.rng.between(1, 10);
        for i in 0..count {
            let name = format!("{}{i}", self.rng.pick(&["a", "b", "len", "p", "s"]));
            match self.rng.below(10) {
                0 => self.function(&name),
                1 => self.feature(&name),
                2 => {
                    let e = self.expr(3);
                    let _ = writeln!(self.out, "param {name} = {e}");
                }
                3 => {
                    let e = self.expr(3);
                    let _ = writeln!(self.out, "product {name} = {e}");
                }
                _ => {
                    let e = self.expr(4);
                    let _ = writeln!(self.out, "let {name} = {e}");
                }
            }
            self.names.push(name);
        }
    }

    fn function(&mut self, name: &str) {
        let arity = self.rng.below(4);
        let params: Vec<String> = (0..arity).map(|i| format!("x{i}")).collect();
        let saved = self.names.len();
        self.names.extend(params.iter().cloned());
        let mut list = params.clone();
        if self.rng.chance(0.3) {
            let d = self.expr(1);
            list.push(format!("opt = {d}"));
        }
        // A function may call itself: recursion, bounded or not, is fair game.
        self.fns.push((name.to_string(), arity));
        let body = self.expr(4);
        self.names.truncate(saved);
        let _ = writeln!(self.out, "fn {name}({}) = {body}", list.join(", "));
    }

    fn feature(&mut self, name: &str) {
        if self.sig.features.is_empty() {
            return;
        }
        let (kind, single, named) = {
            let f = self.rng.pick(&self.sig.features);
            (f.0, f.1.clone(), f.2.clone())
        };
        let _ = writeln!(self.out, "{kind} {name} {{");
        for field in &single {
            if self.rng.chance(0.7) {
                let e = self.expr(3);
                let _ = writeln!(self.out, "    {field} = {e}");
            }
        }
        for word in &named {
            for k in 0..self.rng.below(3) {
                if self.rng.chance(0.5) {
                    let e = self.expr(3);
                    let _ = writeln!(self.out, "    {word} n{k} = {e}");
                } else {
                    let _ = writeln!(self.out, "    {word} n{k} {{");
                    for field in single.iter().take(3) {
                        let e = self.expr(2);
                        let _ = writeln!(self.out, "        {field} = {e}");
                    }
                    let _ = writeln!(self.out, "    }}");
                }
            }
        }
        if self.rng.chance(0.1) {
            let _ = writeln!(self.out, "    unknown_field = 1");
        }
        let _ = writeln!(self.out, "}}");
    }

    /// An expression of at most `depth` levels.
    fn expr(&mut self, depth: usize) -> String {
        if self.budget == 0 || depth == 0 {
            return self.leaf();
        }
        self.budget -= 1;
        let d = depth - 1;
        match self.rng.below(16) {
            0..=2 => self.leaf(),
            3 => {
                let op = *self
                    .rng
                    .pick(&["+", "-", "*", "/", "==", "<", ">=", "and", "or"]);
                format!("{} {op} {}", self.expr(d), self.expr(d))
            }
            4 => format!("({}, {})", self.expr(d), self.expr(d)),
            5 => format!("({}, {}, {})", self.expr(d), self.expr(d), self.expr(d)),
            6 => {
                let n = self.rng.below(5);
                let items: Vec<String> = (0..n).map(|_| self.expr(d)).collect();
                format!("[{}]", items.join(", "))
            }
            7 => format!(
                "[{} for i in {}]",
                self.expr(d),
                if self.rng.chance(0.7) {
                    format!(
                        "range(0, {})",
                        self.rng
                            .pick(&["3", "10", "3", "10", "1000", "3", "10", "1e7"])
                    )
                } else {
                    self.expr(d)
                }
            ),
            8 => format!(
                "if {} then {} else {}",
                self.expr(d),
                self.expr(d),
                self.expr(d)
            ),
            9 => format!("fn(x) => {}", self.expr(d)),
            10 => self.sketch(d),
            11 => {
                let n = self.rng.below(3);
                let fields: Vec<String> =
                    (0..n).map(|i| format!("k{i}: {}", self.expr(d))).collect();
                format!("{{{}}}", fields.join(", "))
            }
            12 => format!(
                "{}.{}",
                self.expr(d),
                self.rng.pick(&["x", "y", "z", "k0", "quality", "line"])
            ),
            13 => format!("{}[{}]", self.expr(d), self.expr(d)),
            14 => self.user_call(d),
            _ => self.builtin_call(d),
        }
    }

    fn leaf(&mut self) -> String {
        match self.rng.below(6) {
            0 | 1 if !self.names.is_empty() => self.rng.pick(&self.names).clone(),
            2 => (*self
                .rng
                .pick(&["true", "false", "\"x\"", "\"\"", "top", "side_xz"]))
            .to_string(),
            3 => format!("-{}", self.number()),
            _ => self.number(),
        }
    }

    fn number(&mut self) -> String {
        let n = if self.rng.chance(0.6) {
            format!("{}", self.rng.below(2000) as f64 / 4.0)
        } else {
            self.rng.pick(NUMBERS).to_string()
        };
        format!("{n}{}", self.rng.pick(UNITS))
    }

    fn point(&mut self) -> String {
        let x = self.rng.below(1200) as f64 - 600.0;
        let y = self.rng.below(1000) as f64 - 500.0;
        if self.rng.chance(0.9) {
            format!("({x}, {y})")
        } else {
            format!("({}, {})", self.number(), self.number())
        }
    }

    fn sketch(&mut self, depth: usize) -> String {
        let view = *self.rng.pick(VIEWS);
        let mut s = format!("sketch({view}) {{ from {}", self.point());
        for _ in 0..self.rng.between(1, 6) {
            let cmd = match self.rng.below(7) {
                0 | 1 => format!("line to {}", self.point()),
                2 => format!("arc to {} through {}", self.point(), self.point()),
                3 => format!("tangent arc to {}", self.point()),
                4 => format!("spline through [{}, {}]", self.point(), self.point()),
                5 => format!("fillet {}", self.expr(depth.min(1))),
                _ => "close".to_string(),
            };
            let _ = write!(s, "; {cmd}");
        }
        s.push_str(" }");
        s
    }

    fn user_call(&mut self, depth: usize) -> String {
        if self.fns.is_empty() {
            return self.builtin_call(depth);
        }
        let (name, arity) = self.rng.pick(&self.fns).clone();
        let n = if self.rng.chance(0.9) {
            arity
        } else {
            self.rng.below(5)
        };
        let args: Vec<String> = (0..n).map(|_| self.expr(depth)).collect();
        format!("{name}({})", args.join(", "))
    }

    fn builtin_call(&mut self, depth: usize) -> String {
        if self.sig.builtins.is_empty() {
            return self.leaf();
        }
        let (name, params) = {
            let b = self.rng.pick(&self.sig.builtins);
            (b.0, b.1.clone())
        };
        let named = self.rng.chance(0.5);
        let mut args = Vec::new();
        for (p, required) in params {
            if required || self.rng.chance(0.3) {
                let e = self.expr(depth);
                args.push(if named { format!("{p}: {e}") } else { e });
                if !named && !required {
                    break;
                }
            }
        }
        if self.rng.chance(0.05) {
            args.push(self.expr(depth));
        }
        format!("{name}({})", args.join(", "))
    }
}

/// A whole small die in the shape of the fender example (product, trim, opening,
/// binder, step draw, two beads) with every number drawn at random, plausible most of
/// the time, and a coarse tolerance so it tessellates quickly.
fn small_die(rng: &mut Rng) -> String {
    let n = |lo: f64, hi: f64, rng: &mut Rng| -> String {
        if rng.chance(0.04) {
            rng.pick(&["0", "-1", "1e6", "1e-6", "1e300"]).to_string()
        } else {
            let t = rng.below(1001) as f64 / 1000.0;
            format!("{:.3}", lo + (hi - lo) * t)
        }
    };
    let length = n(300.0, 1400.0, rng);
    let width = n(200.0, 900.0, rng);
    let crown = n(-20.0, 80.0, rng);
    let tip = n(-6.0, 6.0, rng);
    let trim_r = n(5.0, 120.0, rng);
    let margin = n(40.0, 200.0, rng);
    let fillet = n(10.0, 160.0, rng);
    let wrap = [
        n(-120.0, -40.0, rng),
        n(-120.0, -40.0, rng),
        n(-120.0, -40.0, rng),
    ];
    let binder_width = n(60.0, 260.0, rng);
    let angle = n(-6.0, 6.0, rng);
    let tautness = n(0.0, 100.0, rng);
    let tangent = n(20.0, 120.0, rng);
    let draft = n(2.0, 20.0, rng);
    let punch_r = n(2.0, 20.0, rng);
    let die_r = n(2.0, 20.0, rng);
    let step = n(5.0, 30.0, rng);
    let bead_h = n(2.0, 12.0, rng);
    let bead_r = n(2.0, 10.0, rng);
    let taper = n(5.0, 80.0, rng);
    let bead_out = n(20.0, 150.0, rng);
    let profile = *rng.pick(&["plain", "stepped", "flat"]);
    let degree = *rng.pick(&["(3, 3)", "(2, 3)", "(3, 2)", "(1, 1)"]);
    format!(
        r#"import "std/addendum" as add
import "std/beads" as beads
import "std/sketch" as sk
units mm deg
param tolerance = 1 mm
let length = {length} mm
let width = {width} mm
fn height(i, j) = {crown} mm * (1 - ((i - 2) / 2) * ((i - 2) / 2)) * (1 - ((j - 1.5) / 1.5) * ((j - 1.5) / 1.5))
let net = [[(-length / 2 + i * length / 4, -width / 2 + j * width / 3, height(i, j)) for j in range(0, 4)] for i in range(0, 5)]
let panel = nurbs_surface(degree: {degree}, points: net) |> tip(about: "x", by: {tip} deg)
let trim_line = sk.rectangle(top, (0, 0), length - 60 mm, width - 60 mm, {trim_r} mm)
product part = trim(panel, project(trim_line, panel))
let half_x = length / 2 + {margin} mm
let half_y = width / 2 + {margin} mm
let punch_profile = sketch(top) {{
    from (-half_x, -half_y)
    fillet {fillet}
    line to (half_x, -half_y)
    fillet {fillet}
    line to (half_x, half_y)
    fillet {fillet}
    line to (-half_x, half_y)
    fillet {fillet}
    close
}}
let wrap_x = sketch(side_xz) {{ from (-half_x - 50 mm, {w0}); spline through [(0, {w1}), (half_x + 50 mm, {w2})] }}
let wrap_y = sketch(side_yz) {{ from (-half_y - 50 mm, {w0}); spline through [(0, {w1}), (half_y + 50 mm, {w2})] }}
punch_opening opening {{
    top = punch_profile
    side a = wrap_x
    side b = wrap_y
    side c = wrap_x
    side d = wrap_y
    corners {{ tangent = {tangent} % }}
}}
blankholder binder {{
    opening = opening
    width = {binder_width} mm
    angle = {angle} deg
    corners {{ tautness = {tautness} % }}
}}
fn plain(product, opening) = add.wall(product, opening, draft: {draft} deg, punch_radius: {punch_r} mm, die_radius: {die_r} mm)
fn stepped(product, opening) = add.step(product, opening, step_depth: {step} mm, step_width: {step} mm, draft: {draft} deg)
fn flat(product, opening) = add.flat_binder(product, opening, flat: 30 mm, draft: {draft} deg)
step_draw addendum {{
    product = part
    opening = opening
    binder = binder
    section a {{ at = ((0, -width / 4), (0, -half_y - 60 mm)); profile = {profile} }}
    section b {{ at = ((length / 4, 0), (half_x + 60 mm, 0)); profile = plain }}
    section c {{ at = ((0, width / 4), (0, half_y + 60 mm)); profile = plain }}
    section d {{ at = ((-length / 4, 0), (-half_x - 60 mm, 0)); profile = plain }}
}}
bead edge {{
    binder = binder
    line = sketch(top) {{ from (-length / 4, -half_y - {bead_out} mm); line to (length / 4, -half_y - {bead_out} mm) }}
    profile = beads.round(height: {bead_h} mm, radius: {bead_r} mm)
    taper = {taper} mm
    force = 200
}}
"#,
        w0 = wrap[0],
        w1 = wrap[1],
        w2 = wrap[2],
    )
}
