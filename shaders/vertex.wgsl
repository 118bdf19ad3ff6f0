// vertex.wgsl: the one vertex interface of every mesh pass (surface, prisms, shadow map, NCS
// bake). The Rust side is `mesh::Vertex` (locations 0-4) and `geometry::prisms::PrismVertex`
// (adds location 5, the prism's index).
#define_import_path pomkit::vertex

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    // world length per unit of u and of v (S_tangent, S_binormal of Chen & Chang)
    @location(4) uv_scale: vec2<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv_scale: vec2<f32>,
    // prisms: the index of the prism
    @location(5) @interpolate(flat) prism: u32,
}

// The vertex at clip position `clip`, passing the attributes through.
fn pass_through(v: VertexIn, clip: vec4<f32>) -> VertexOut {
    var o: VertexOut;
    o.clip = clip;
    o.world = v.position;
    o.normal = v.normal;
    o.uv = v.uv;
    o.tangent = v.tangent;
    o.uv_scale = v.uv_scale;
    o.prism = 0u;
    return o;
}
