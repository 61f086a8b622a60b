//! Colour rules the scene, the renderer and the evaluator share: sRGB decoding and OKLab
//! (Björn Ottosson's matrices; `shaders/lib/common.wgsl` holds the same for the GPU).

/// An sRGB8 channel → linear light.
pub fn linear_from_srgb8(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear RGB → OKLab (L, a, b).
pub fn oklab_from_linear([r, g, b]: [f32; 3]) -> [f32; 3] {
    let l = (0.412_221_46 * r + 0.536_332_55 * g + 0.051_445_995 * b).cbrt();
    let m = (0.211_903_5 * r + 0.680_699_5 * g + 0.107_396_96 * b).cbrt();
    let s = (0.088_302_46 * r + 0.281_718_85 * g + 0.629_978_7 * b).cbrt();
    [
        0.210_454_26 * l + 0.793_617_8 * m - 0.004_072_047 * s,
        1.977_998_5 * l - 2.428_592_2 * m + 0.450_593_7 * s,
        0.025_904_037 * l + 0.782_771_77 * m - 0.808_675_77 * s,
    ]
}

/// sRGB8 → OKLab (L, a, b).
pub fn oklab_from_srgb8(rgb: [u8; 3]) -> [f32; 3] {
    oklab_from_linear(rgb.map(linear_from_srgb8))
}
