// Draw lists: the texels the cull pass visits in our schedule, so it never scans a face.
// Per slot, one buffer: LIST_HEADER counts (one per face), then each face's n² entries
// (x | y << 16). Per (slot, face), the cull's indirect dispatch arguments (x, y, z, unused)
// in `list_args`, with x = workgroups of 64 over the entries. Filled by the runs pass (run
// heads of stable faces) and the shade pass (eye texels lit this frame). The includer
// declares `list: array<atomic<u32>>` and `list_args: array<atomic<u32>>`, read_write, and
// includes lib/common.wgsl (`LIST_HEADER`).

fn list_push(slot: u32, face: u32, n: u32, t: vec2<u32>) {
    let index = atomicAdd(&list[face], 1u);
    if index % 64u == 0u {
        atomicAdd(&list_args[(slot * 6u + face) * 4u], 1u);
    }
    atomicStore(&list[LIST_HEADER + face * n * n + index], t.x | (t.y << 16u));
}
