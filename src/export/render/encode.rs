//! A canvas as PNG bytes: 8-bit RGB, fixed compression and filter settings, no time or
//! text chunks, so the same picture is always the same bytes.

use super::raster::Canvas;

/// The PNG file of `canvas`. Encoding into memory cannot fail for a canvas's sizes
/// (1 to [`super::MAX_SIDE`] pixels a side), so an encoder error is reported as a
/// message rather than a panic only for completeness.
pub fn encode_png(canvas: &Canvas) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let width = u32::try_from(canvas.width()).map_err(|_| "the picture is too wide")?;
    let height = u32::try_from(canvas.height()).map_err(|_| "the picture is too tall")?;
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Default);
        encoder.set_filter(png::FilterType::Sub);
        encoder.set_adaptive_filter(png::AdaptiveFilterType::NonAdaptive);
        let mut writer = encoder
            .write_header()
            .map_err(|e| format!("cannot encode the PNG: {e}"))?;
        writer
            .write_image_data(canvas.pixels())
            .map_err(|e| format!("cannot encode the PNG: {e}"))?;
        writer
            .finish()
            .map_err(|e| format!("cannot encode the PNG: {e}"))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_canvas_round_trips_through_png() {
        let mut c = Canvas::new(3, 2, [10, 20, 30]);
        c.put(2, 1, [200, 100, 0]);
        let bytes = encode_png(&c).expect("encodes");
        assert_eq!(encode_png(&c).expect("encodes"), bytes, "deterministic");
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("a frame");
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(&buf[..info.buffer_size()], c.pixels());
    }
}
