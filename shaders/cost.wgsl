// cost.wgsl: the per-pixel cost counters (AOVs `fetches` and `bytes`), counted only in the
// variants that write them (shader def COUNT_FETCHES; elsewhere `fetched` is empty and compiles
// away, so a frame that does not ask for them costs and renders exactly as before).
//
// What counts: every read of the method's search (the view ray and the light rays) from the
// height field, the max pyramid, the cone map, the walk data of NCS and curved relief, the
// distance volume and the prisms' data. The shading normal (the same four samples for every method) and the albedo are
// not counted: the counts are the method's cost above Flat.
//   fetches: texel fetch operations. A textureLoad or a storage read of one map value is 1; a
//            textureGather is 4 (four texels); a hardware-filtered sample is 1 (one texture
//            instruction; its filter reads 4 texels, 8 between two levels).
//   bytes:   the bytes those fetches read: 4 per float32 texel, 16 for a filtered bilinear sample
//            (32 trilinear), 16 per gather, 16 per walk record (vec4), 96 per prism visited.
//   chain:   the longest chain of dependent fetches: the rounds of fetches in which a round's
//            addresses wait on a value the round before it read (a traversal's next node, a
//            walk's next step, a binary search's next midpoint, a shadow ray from the hit). A
//            search whose addresses all follow from the ray (the POM family's linear search)
//            is one round however many fetches it takes; a GPU issues them together, where it
//            waits a fetch's latency for each round. The methods mark each new round
//            (`chained`); 0 where the search fetched nothing.
//   fragments: the fragment invocations of the surface pass at the pixel (overdraw): every
//            fragment the method's geometry puts there that runs its shader, whether it then
//            writes or discards (a prism face tested and missed counts). Counted only in the
//            variants that ask (shader def COUNT_FRAGMENTS), by an atomic add into a storage
//            buffer of one u32 per pixel (group 0, binding 3), cleared before the pass.
#define_import_path pomkit::cost

#import pomkit::view::V

#ifdef COUNT_FRAGMENTS
@group(0) @binding(3) var<storage, read_write> fragment_counts: array<atomic<u32>>;
#endif

// Count this fragment at pixel `px` (the fragment's position, `clip.xy`): call first in a
// surface pass's fragment entry point, before any discard.
fn count_fragment(px: vec2<f32>) {
#ifdef COUNT_FRAGMENTS
    let i = u32(px.y) * u32(V.frame_width) + u32(px.x);
    atomicAdd(&fragment_counts[i], 1u);
#endif
}

#ifdef COUNT_FETCHES
var<private> cost_fetches: u32;
var<private> cost_bytes: u32;
var<private> cost_rounds: u32;
#endif

// `n` fetches reading `b` bytes (the first fetch opens the first round).
fn fetched(n: u32, b: u32) {
#ifdef COUNT_FETCHES
    cost_fetches = cost_fetches + n;
    cost_bytes = cost_bytes + b;
    cost_rounds = max(cost_rounds, 1u);
#endif
}

// The fetches from here on wait on a value read before: a new round of the chain.
fn chained() {
#ifdef COUNT_FETCHES
    cost_rounds = cost_rounds + 1u;
#endif
}

// The counts so far: (fetches, bytes, chain, 0).
fn cost_counts() -> vec4<u32> {
#ifdef COUNT_FETCHES
    return vec4<u32>(cost_fetches, cost_bytes, select(0u, cost_rounds, cost_fetches > 0u), 0u);
#else
    return vec4<u32>(0u);
#endif
}
