//! The viewer's page and three.js, embedded in the binary so the viewer works offline:
//! `page/` is ours; `vendor/three/` is three.js as published on npm at the version
//! `package.json` pins (copied by `scripts/vendor-three`, MIT licence in
//! `vendor/three/LICENSE`, served at `/vendor/three/LICENSE`).

/// One embedded file.
pub(crate) struct Asset {
    /// Its `Content-Type`.
    pub content_type: &'static str,
    /// Its bytes.
    pub bytes: &'static [u8],
}

const HTML: &str = "text/html; charset=utf-8";
const JS: &str = "text/javascript; charset=utf-8";
const CSS: &str = "text/css; charset=utf-8";
const TEXT: &str = "text/plain; charset=utf-8";

/// Every served file by its path.
const FILES: &[(&str, &str, &[u8])] = &[
    ("/", HTML, include_bytes!("page/index.html")),
    ("/viewer.js", JS, include_bytes!("page/viewer.js")),
    ("/viewer.css", CSS, include_bytes!("page/viewer.css")),
    (
        "/vendor/three/LICENSE",
        TEXT,
        include_bytes!("vendor/three/LICENSE"),
    ),
    (
        "/vendor/three/VERSION",
        TEXT,
        include_bytes!("vendor/three/VERSION"),
    ),
    (
        "/vendor/three/build/three.module.js",
        JS,
        include_bytes!("vendor/three/build/three.module.js"),
    ),
    (
        "/vendor/three/build/three.core.js",
        JS,
        include_bytes!("vendor/three/build/three.core.js"),
    ),
    (
        "/vendor/three/examples/jsm/controls/OrbitControls.js",
        JS,
        include_bytes!("vendor/three/examples/jsm/controls/OrbitControls.js"),
    ),
    (
        "/vendor/three/examples/jsm/loaders/GLTFLoader.js",
        JS,
        include_bytes!("vendor/three/examples/jsm/loaders/GLTFLoader.js"),
    ),
    (
        "/vendor/three/examples/jsm/utils/BufferGeometryUtils.js",
        JS,
        include_bytes!("vendor/three/examples/jsm/utils/BufferGeometryUtils.js"),
    ),
    (
        "/vendor/three/examples/jsm/utils/SkeletonUtils.js",
        JS,
        include_bytes!("vendor/three/examples/jsm/utils/SkeletonUtils.js"),
    ),
];

/// The embedded file served at `path` (`/index.html` is `/`).
pub(crate) fn get(path: &str) -> Option<Asset> {
    let path = if path == "/index.html" { "/" } else { path };
    FILES
        .iter()
        .find(|(p, _, _)| *p == path)
        .map(|&(_, content_type, bytes)| Asset {
            content_type,
            bytes,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_and_three_are_served_with_their_types() {
        let page = get("/").expect("the page is embedded");
        assert!(page.content_type.starts_with("text/html"));
        assert!(std::str::from_utf8(page.bytes).is_ok_and(|t| t.contains("viewer.js")));
        let three = get("/vendor/three/build/three.module.js").expect("three.js is embedded");
        assert_eq!(three.content_type, JS);
        let licence = get("/vendor/three/LICENSE").expect("the licence is kept");
        assert!(std::str::from_utf8(licence.bytes).is_ok_and(|t| t.contains("MIT License")));
        assert!(get("/../Cargo.toml").is_none());
    }
}
