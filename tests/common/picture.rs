//! A PNG decoded to 8-bit RGB pixels, for the tests that check what a picture shows
//! (`render`, `diff --png`, the viewer's browser screenshots).

/// A decoded picture: width, height and RGB bytes (alpha, if any, dropped).
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
}

impl Image {
    /// Decodes an 8-bit RGB or RGBA PNG.
    pub fn decode(bytes: &[u8]) -> Image {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("a frame");
        assert_eq!(info.bit_depth, png::BitDepth::Eight, "an 8-bit PNG");
        buf.truncate(info.buffer_size());
        let rgb = match info.color_type {
            png::ColorType::Rgb => buf,
            png::ColorType::Rgba => buf
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect(),
            other => panic!("an RGB or RGBA PNG, not {other:?}"),
        };
        Image {
            width: info.width as usize,
            height: info.height as usize,
            rgb,
        }
    }

    /// Reads and decodes the PNG file at `path`.
    pub fn read(path: &std::path::Path) -> Image {
        Image::decode(&std::fs::read(path).expect("the picture was written"))
    }

    /// The pixel at column `x`, row `y`.
    pub fn at(&self, x: usize, y: usize) -> [u8; 3] {
        let i = 3 * (y * self.width + x);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Every pixel, row by row.
    pub fn pixels(&self) -> impl Iterator<Item = [u8; 3]> + '_ {
        self.rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]])
    }
}
