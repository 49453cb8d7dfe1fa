//! `dieface render`: the real binary draws a script's geometry as a PNG, and the
//! pixels say so (background at the corners, the product's glTF colour where the
//! product is, a different picture from another view), byte for byte the same each
//! time; bad sizes and script errors leave an earlier picture as it was.

mod common;

use std::path::{Path, PathBuf};

use dieface::export::render::raster::to_srgb;

/// The script of the pixel tests ([`common::BUMPED_PANEL`]).
const SCRIPT: &str = common::BUMPED_PANEL;

/// The picture size of the pixel tests: the part is square, so it is drawn 360 px
/// high and wide, centred at (400, 200), clear of the legend at the top left.
const SIZE: &str = "800x400";

fn project(name: &str) -> PathBuf {
    let dir = common::fresh_dir("render", name);
    std::fs::write(dir.join("part.die"), SCRIPT).expect("write script");
    dir
}

fn dieface(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    common::run_dieface(dir, args)
}

/// Renders `part.die` in `dir` to `out` with extra `args`; the run must succeed.
fn render(dir: &Path, out: &str, args: &[&str]) -> Vec<u8> {
    let mut all = vec!["render", "part.die", "-o", out];
    all.extend_from_slice(args);
    let (code, stdout, stderr) = dieface(dir, &all);
    assert_eq!(code, Some(0), "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.contains(&format!("wrote {out}")), "{stdout}");
    std::fs::read(dir.join(out)).expect("the picture")
}

use common::picture::Image;

const WHITE: [u8; 3] = [255, 255, 255];

/// How far `pixel` is from `color` (linear RGB) lit by any amount from 30 % to 100 %
/// (the shading's range): the largest channel difference at the best lighting.
fn off_shade(pixel: [u8; 3], color: [f64; 3]) -> u8 {
    (30..=100)
        .map(|k| {
            let lit = to_srgb(color.map(|c| c * k as f64 / 100.0));
            (0..3).map(|i| pixel[i].abs_diff(lit[i])).max().unwrap_or(0)
        })
        .min()
        .unwrap_or(u8::MAX)
}

/// The base colour of the glTF material named `kind` in the GLB `bytes`.
fn material_color(glb: &[u8], kind: &str) -> [f64; 3] {
    let len = u32::from_le_bytes(glb[12..16].try_into().expect("4 bytes")) as usize;
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).expect("JSON chunk");
    let material = json["materials"]
        .as_array()
        .expect("materials")
        .iter()
        .find(|m| m["name"] == kind)
        .unwrap_or_else(|| panic!("a `{kind}` material"));
    let c = &material["pbrMetallicRoughness"]["baseColorFactor"];
    [0, 1, 2].map(|i| c[i].as_f64().expect("a number"))
}

#[test]
fn the_same_script_gives_the_same_bytes() {
    let dir = project("same");
    let a = render(&dir, "a.png", &["--size", SIZE]);
    let b = render(&dir, "b.png", &["--size", SIZE]);
    assert!(a.starts_with(b"\x89PNG\r\n\x1a\n"), "a PNG signature");
    assert_eq!(a, b, "two renders of one script are byte-identical");
}

#[test]
fn the_top_view_shows_the_product_in_its_exported_colour() {
    let dir = project("top");
    let (code, _, stderr) = dieface(&dir, &["build", "part.die", "-o", "part.glb"]);
    assert_eq!(code, Some(0), "{stderr}");
    let glb = std::fs::read(dir.join("part.glb")).expect("the glb");
    let product = material_color(&glb, "product");
    let plain = material_color(&glb, "let");

    let img = Image::decode(&render(&dir, "top.png", &["--view", "top", "--size", SIZE]));
    assert_eq!((img.width, img.height), (800, 400));
    for (x, y) in [(0, 0), (799, 0), (0, 399), (799, 399)] {
        assert_eq!(img.at(x, y), WHITE, "corner ({x}, {y}) is the background");
    }
    let drawn = img.pixels().filter(|p| *p != WHITE).count();
    assert!(
        drawn > 800 * 400 / 4,
        "the part covers much of the picture: {drawn}"
    );
    // The part's middle (the panel's bump) is the product, lit from above.
    for (x, y) in [(400, 200), (380, 180), (420, 220), (340, 260)] {
        let p = img.at(x, y);
        assert!(
            off_shade(p, product) <= 3,
            "({x}, {y}) = {p:?}: the product's colour {product:?}"
        );
        assert!(off_shade(p, plain) > 12, "({x}, {y}) is not the plain grey");
    }
    // The plate shows round the panel (a 50 mm rim of 300 mm: 60 px of 360).
    let rim = img.at(400, 30);
    assert!(
        off_shade(rim, plain) <= 3,
        "the plate's rim {rim:?} in the plain colour {plain:?}"
    );
    // The legend names the kinds beside their swatches, top left.
    let legend = (0..60)
        .flat_map(|x| (0..30).map(move |y| (x, y)))
        .filter(|&(x, y)| img.at(x, y) != WHITE)
        .count();
    assert!(legend > 50, "a legend is drawn: {legend} pixels");
}

#[test]
fn views_differ() {
    let dir = project("views");
    let top = Image::decode(&render(&dir, "top.png", &["--view", "top", "--size", SIZE]));
    let iso = Image::decode(&render(&dir, "iso.png", &["--size", SIZE]));
    let side = Image::decode(&render(
        &dir,
        "side.png",
        &["--view", "side", "--size", SIZE],
    ));
    let differ = |a: &Image, b: &Image| a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert!(differ(&top, &iso) > 800 * 400 / 10, "top and iso differ");
    assert!(differ(&top, &side) > 800 * 400 / 10, "top and side differ");
    // From the side (+X) the sheets are seen nearly edge on: a thin band of pixels.
    let side_drawn = side.pixels().filter(|p| *p != WHITE).count();
    let top_drawn = top.pixels().filter(|p| *p != WHITE).count();
    assert!(
        side_drawn * 3 < top_drawn,
        "side {side_drawn} px, top {top_drawn} px"
    );
}

#[test]
fn a_bad_size_or_a_script_error_leaves_the_last_picture() {
    let dir = project("errors");
    let good = render(&dir, "view.png", &["--size", SIZE]);
    for size in [
        "800",
        "0x100",
        "100x9000",
        "8192x8192",
        "wide x tall",
        "-800x400",
    ] {
        let arg = format!("--size={size}");
        let (code, _, stderr) = dieface(&dir, &["render", "part.die", "-o", "view.png", &arg]);
        assert_eq!(code, Some(2), "--size {size}: {stderr}");
        assert!(stderr.contains("--size"), "names the option: {stderr}");
    }
    let (code, _, stderr) = dieface(&dir, &["render", "part.die", "-o", "view.jpg"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains(".png"), "{stderr}");
    let (code, _, stderr) = dieface(
        &dir,
        &["render", "part.die", "-o", "view.png", "--view", "left"],
    );
    assert_eq!(code, Some(2), "{stderr}");

    std::fs::write(dir.join("part.die"), "units mm\nlet a = 1 mm + 2 deg\n").expect("write");
    let (code, _, stderr) = dieface(
        &dir,
        &["render", "part.die", "-o", "view.png", "--color", "never"],
    );
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("no picture written"), "{stderr}");
    assert_eq!(
        std::fs::read(dir.join("view.png")).expect("still there"),
        good,
        "untouched"
    );
    assert!(
        common::temp_files(&dir).is_empty(),
        "no temporary file left"
    );

    std::fs::write(dir.join("part.die"), "units mm\nparam depth = 3 mm\n").expect("write");
    let (code, _, stderr) = dieface(&dir, &["render", "part.die", "-o", "view.png"]);
    assert_eq!(code, Some(1), "nothing to draw: {stderr}");
    assert!(stderr.contains("nothing to draw"), "{stderr}");
    assert_eq!(
        std::fs::read(dir.join("view.png")).expect("still there"),
        good,
        "untouched"
    );
}
