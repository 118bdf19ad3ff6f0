// vertex.wgsl: the one vertex interface of every mesh pass (surface, prisms, shadow map, NCS
// bake). The Rust side is `mesh::Vertex` (locations 0-4). A method's own geometry may add one
// attribute at location 5: the prisms' index (their own pass), or, in the surface pass with
// the shader def VERTEX_EXTRA, a vec4 of the method's that the march reads as `Ray::extra`
// (interpolated across the triangle).
#define_import_path pomkit::vertex

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    // world length per unit of u and of v (S_tangent, S_binormal of Chen & Chang)
    @location(4) uv_scale: vec2<f32>,
#ifdef VERTEX_EXTRA
    @location(5) extra: vec4<f32>,
#endif
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
#ifdef VERTEX_EXTRA
    @location(6) extra: vec4<f32>,
#endif
#ifdef PRISM_CORNER
    // prisms: the fragment's barycentrics in its boundary face (each corner one-hot) and its
    // offset from the face's centre (interpolated, not a flat centre: on lavapipe Prism paid
    // 6-8 % for the flat one, 4-5 % for these two)
    @location(7) corner: vec3<f32>,
    @location(8) from_centre: vec3<f32>,
#endif
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
#ifdef VERTEX_EXTRA
    o.extra = v.extra;
#endif
#ifdef PRISM_CORNER
    o.corner = vec3<f32>(0.0);
    o.from_centre = vec3<f32>(0.0);
#endif
    return o;
}
