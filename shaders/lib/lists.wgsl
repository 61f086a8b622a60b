// Draw lists: the texels the cull pass visits in our schedule, so it never scans a face.
// Per slot, one buffer: LIST_HEADER counts (one per face), then each face's n² entries
// (x | y << 16). Filled by the runs pass (run heads of stable faces) and the shade pass (eye
// texels lit this frame). The includer declares `list: array<atomic<u32>>`, read_write, and
// includes lib/common.wgsl (`LIST_HEADER`).

fn list_push(face: u32, n: u32, t: vec2<u32>) {
    let index = atomicAdd(&list[face], 1u);
    atomicStore(&list[LIST_HEADER + face * n * n + index], t.x | (t.y << 16u));
}
