//! Fuzzes camera-path files: any bytes must give a checked path or an error, never a panic;
//! and every camera of a path that loads is usable (finite, a unit view direction, a field
//! of view and clip planes a projection can take).
#![no_main]

use libfuzzer_sys::fuzz_target;
use texel_runtime::path::CameraPath;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(path) = CameraPath::from_ron_str(text, "fuzz.ron") else {
        return;
    };
    let last = path.frames.saturating_sub(1);
    for i in [0, 1, last / 2, last, path.frames.saturating_add(7)] {
        let c = path.camera(i, 1.0);
        assert!(c.position.is_finite(), "frame {i}: {c:?}");
        assert!((c.forward.length() - 1.0).abs() < 1e-3, "frame {i}: {c:?}");
        assert!(c.fov_y.is_finite() && c.fov_y > 0.0 && c.fov_y < std::f32::consts::PI);
        assert!(c.near > 0.0 && c.far > c.near, "frame {i}: {c:?}");
        if let Some(h) = c.ortho_height {
            assert!(h.is_finite() && h > 0.0, "frame {i}: {c:?}");
        }
        let m = c.projection(16.0 / 9.0) * c.view();
        assert!(m.is_finite(), "frame {i}: {c:?}");
    }
});
