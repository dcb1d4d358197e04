//! Animated PNG (APNG) of a sequence's frames, written with the `png` crate's APNG encoder. Browsers
//! play it in an `<img>`, so the report stays self-contained; viewers without APNG show frame 0.

use crate::{Error, Result};
use image::RgbImage;

/// Encodes equally sized RGB frames, each shown `delay_ms`, looping forever.
pub fn encode(frames: &[RgbImage], delay_ms: u16) -> Result<Vec<u8>> {
    let err = |e: png::EncodingError| Error::io_text("<APNG encoder>".into(), e.to_string());
    let first = frames
        .first()
        .ok_or_else(|| Error::param("an animation needs at least one frame".into()))?;
    let (w, h) = first.dimensions();
    if let Some((i, f)) = frames
        .iter()
        .enumerate()
        .find(|(_, f)| f.dimensions() != (w, h))
    {
        return Err(Error::param(format!(
            "animation frame {i} is {}x{}, frame 0 is {w}x{h}",
            f.width(),
            f.height()
        )));
    }
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_animated(frames.len() as u32, 0).map_err(err)?;
        encoder.set_frame_delay(delay_ms, 1000).map_err(err)?;
        let mut writer = encoder.write_header().map_err(err)?;
        for f in frames {
            writer.write_image_data(f.as_raw()).map_err(err)?;
        }
        writer.finish().map_err(err)?;
    }
    Ok(out)
}

/// Frames side by side, left to right, on one canvas (e.g. shaded | error map).
pub fn side_by_side(parts: &[&RgbImage]) -> RgbImage {
    let w: u32 = parts.iter().map(|p| p.width()).sum();
    let h = parts.iter().map(|p| p.height()).max().unwrap_or(0);
    let mut canvas = RgbImage::new(w, h);
    let mut x0 = 0;
    for p in parts {
        image::imageops::replace(&mut canvas, *p, x0 as i64, 0);
        x0 += p.width();
    }
    canvas
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_round_trip_through_the_decoder() {
        let frames: Vec<RgbImage> = (0..3u8)
            .map(|k| RgbImage::from_pixel(4, 2, image::Rgb([k * 80, 10, 200])))
            .collect();
        let bytes = encode(&frames, 125).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let control = reader.info().animation_control.expect("an APNG");
        assert_eq!((control.num_frames, control.num_plays), (3, 0));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        for k in 0..3u8 {
            reader.next_frame(&mut buf).unwrap();
            assert_eq!(&buf[..3], &[k * 80, 10, 200], "frame {k}");
            let fc = reader.info().frame_control.unwrap();
            assert_eq!((fc.delay_num, fc.delay_den), (125, 1000));
        }
    }

    #[test]
    fn unequal_frames_are_refused() {
        let frames = [RgbImage::new(4, 2), RgbImage::new(2, 2)];
        assert_eq!(
            encode(&frames, 100).unwrap_err().to_string(),
            "animation frame 1 is 2x2, frame 0 is 4x2"
        );
        assert!(encode(&[], 100).is_err());
    }
}
