//! A shaded preview of a height field.

use oficina_io::Heightmap;

/// Lambert shading with light from the upper left, rows flipped back so the top of the
/// picture is the largest Y (as the source image was). 8-bit gray, row-major.
pub fn shade(map: &Heightmap) -> Vec<u8> {
    let (w, h) = (map.width, map.height);
    let light = {
        let v = [-1.0f64, 1.0, 1.5];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    };
    let mut out = Vec::with_capacity(w * h);
    for row in 0..h {
        let iy = h - 1 - row;
        for ix in 0..w {
            let zx = |x: usize| map.at(x, iy) as f64;
            let zy = |y: usize| map.at(ix, y) as f64;
            let dzdx = (zx((ix + 1).min(w - 1)) - zx(ix.saturating_sub(1))) / (2.0 * map.pixel);
            let dzdy = (zy((iy + 1).min(h - 1)) - zy(iy.saturating_sub(1))) / (2.0 * map.pixel);
            let n = (dzdx * dzdx + dzdy * dzdy + 1.0).sqrt();
            let lambert = (-dzdx * light[0] - dzdy * light[1] + light[2]) / n;
            out.push((40.0 + 215.0 * lambert.clamp(0.0, 1.0)) as u8);
        }
    }
    out
}

/// Writes the shaded preview as a PNG.
pub fn render_png(map: &Heightmap, path: &std::path::Path) -> Result<(), String> {
    let pixels = shade(map);
    image::save_buffer(
        path,
        &pixels,
        map.width as u32,
        map.height as u32,
        image::ExtendedColorType::L8,
    )
    .map_err(|e| format!("{}: cannot write the preview: {e}", path.display()))
}

/// The shaded preview as PNG bytes (for a page).
pub fn png_bytes(map: &Heightmap) -> Result<Vec<u8>, String> {
    let mut out = std::io::Cursor::new(Vec::new());
    image::write_buffer_with_format(
        &mut out,
        &shade(map),
        map.width as u32,
        map.height as u32,
        image::ExtendedColorType::L8,
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("cannot encode the preview: {e}"))?;
    Ok(out.into_inner())
}
