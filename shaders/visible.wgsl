// Visible: marks every probe texel whose key some pixel of the final frame holds, in a
// bitset; its population count is the "screen-visible texels" counter.
// crates/render/src/passes/visible.rs.

@group(0) @binding(0) var keys: texture_2d<u32>;
@group(0) @binding(1) var<storage, read_write> bits: array<atomic<u32>>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(keys);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    let key = textureLoad(keys, gid.xy, 0).r;
    if key == 0u {
        return;
    }
    let k = key - 1u;
    let word = k >> 5u;
    let bit = 1u << (k & 31u);
    // Most pixels repeat a neighbour's texel: read first, and write only a new bit.
    if word < arrayLength(&bits) && (atomicLoad(&bits[word]) & bit) == 0u {
        atomicOr(&bits[word], bit);
    }
}
