// Texture sampling without samplers or bindless (crates/render/src/textures.rs): every image
// and its mip chain sit in one block of the atlas, read with textureLoad; wrap modes, the
// mip level and the filter are applied here, inside the image's own rectangle, so nothing
// bleeds between images. The includer binds the atlas, the records and the surfaces at
// group 0, bindings 2-4.

struct TexInfo {
    origin: vec2<u32>,
    size: vec2<u32>,
    layer: u32,
    mips: u32,
    // Bit 0 sRGB, bit 1 linear filter, bits 2-3 wrap U, 4-5 wrap V (0 repeat, 1 mirror, 2 clamp).
    flags: u32,
    _pad: u32,
}

struct Surface {
    albedo: u32,
    normal: u32,
    uv_scale: vec2<f32>,
}

const NO_TEXTURE: u32 = 0xffffffffu;

@group(0) @binding(2) var atlas: texture_2d_array<f32>;
@group(0) @binding(3) var<storage, read> tex_infos: array<TexInfo>;
@group(0) @binding(4) var<storage, read> surfaces: array<Surface>;

// Origin and size of mip `level` of `info` (mips 1.. stacked right of mip 0).
fn mip_rect(info: TexInfo, level: u32) -> vec4<u32> {
    if level == 0u {
        return vec4(info.origin, info.size);
    }
    var y = info.origin.y;
    var s = info.size;
    for (var k = 1u; k <= level; k++) {
        s = max(s / 2u, vec2(1u));
        if k < level {
            y += s.y;
        }
    }
    return vec4(info.origin.x + info.size.x, y, s);
}

fn wrap_coord(i: i32, n: i32, mode: u32) -> i32 {
    if mode == 2u {
        return clamp(i, 0, n - 1);
    }
    let m = ((i % n) + n) % n;
    if mode == 1u {
        // Mirrored: every other tile reversed.
        let tile = (i - m) / n;
        if (tile & 1) != 0 {
            return n - 1 - m;
        }
    }
    return m;
}

fn srgb_decode(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3(2.4)), c / 12.92, c <= vec3(0.04045));
}

// One pixel of mip rectangle `r`, wrapped.
fn tex_fetch(info: TexInfo, r: vec4<u32>, p: vec2<i32>) -> vec4<f32> {
    let n = vec2<i32>(r.zw);
    let q = vec2(
        wrap_coord(p.x, n.x, (info.flags >> 2u) & 3u),
        wrap_coord(p.y, n.y, (info.flags >> 4u) & 3u),
    );
    let v = textureLoad(atlas, vec2<i32>(r.xy) + q, info.layer, 0);
    if (info.flags & 1u) != 0u {
        return vec4(srgb_decode(v.rgb), v.a);
    }
    return v;
}

// One mip level at `uv` (1 = the whole image): the nearest pixel, or bilinear.
fn tex_level(info: TexInfo, level: u32, uv: vec2<f32>) -> vec4<f32> {
    let r = mip_rect(info, level);
    let p = uv * vec2<f32>(r.zw);
    if (info.flags & 2u) == 0u {
        return tex_fetch(info, r, vec2<i32>(floor(p)));
    }
    let q = p - 0.5;
    let i = vec2<i32>(floor(q));
    let f = q - floor(q);
    let a = mix(tex_fetch(info, r, i), tex_fetch(info, r, i + vec2(1, 0)), f.x);
    let b = mix(tex_fetch(info, r, i + vec2(0, 1)), tex_fetch(info, r, i + vec2(1, 1)), f.x);
    return mix(a, b, f.y);
}

// The level of detail of a footprint whose UV derivatives are `dx`, `dy` (log2 of the
// image pixels it spans along its longer side).
fn tex_lod(info: TexInfo, dx: vec2<f32>, dy: vec2<f32>) -> f32 {
    let size = vec2<f32>(info.size);
    let span = max(length(dx * size), length(dy * size));
    return log2(max(span, 1e-8));
}

// Samples texture `index` at `uv` for a footprint of UV derivatives `dx`, `dy`: nearest
// filtering takes the nearest mip level, linear blends the two around it.
fn tex_sample(index: u32, uv: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>) -> vec4<f32> {
    let info = tex_infos[index];
    let top = f32(info.mips - 1u);
    let lod = clamp(tex_lod(info, dx, dy), 0.0, top);
    if (info.flags & 2u) == 0u {
        return tex_level(info, u32(round(lod)), uv);
    }
    let l0 = u32(floor(lod));
    let l1 = min(l0 + 1u, info.mips - 1u);
    return mix(tex_level(info, l0, uv), tex_level(info, l1, uv), fract(lod));
}

// A surface's texture coordinates and their footprint: the mesh UV × the surface's scale.
struct SurfaceUv {
    uv: vec2<f32>,
    dx: vec2<f32>,
    dy: vec2<f32>,
}

// The albedo texture's colour (linear, alpha), white when the surface has none.
fn surface_texture_colour(s: Surface, t: SurfaceUv) -> vec4<f32> {
    if s.albedo == NO_TEXTURE {
        return vec4(1.0);
    }
    return tex_sample(s.albedo, t.uv, t.dx, t.dy);
}

// The normal-mapped normal of a surface point whose geometric normal is `n` on a triangle
// whose U and V have world gradients `grad_u`, `grad_v` (its cotangent frame: no tangent
// attribute needed) at UV footprint `t`; `n` itself without a normal map. Green points up
// the image (−V), as glTF.
fn surface_shading_normal(s: Surface, n: vec3<f32>, grad_u: vec3<f32>, grad_v: vec3<f32>, t: SurfaceUv) -> vec3<f32> {
    if s.normal == NO_TEXTURE {
        return n;
    }
    let m = tex_sample(s.normal, t.uv, t.dx, t.dy).xyz * 2.0 - 1.0;
    let tangent = grad_u;
    let bitangent = grad_v;
    let scale = inverseSqrt(max(max(dot(tangent, tangent), dot(bitangent, bitangent)), 1e-20));
    let shaded = tangent * scale * m.x - bitangent * scale * m.y + n * m.z;
    let len = length(shaded);
    if len < 1e-6 {
        return n;
    }
    return shaded / len;
}
