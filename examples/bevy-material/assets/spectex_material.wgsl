// A Bevy Material2d fragment shader that imports a module written by `spectex export --wgsl`
// (registered by src/main.rs under the import path `spectex::model`) and shows the model, one
// framebuffer pixel per `scale` model pixels from `offset` (the CPU's `--offset`/`--scale`).
#import bevy_sprite::mesh2d_vertex_output::VertexOutput
#import spectex::model::spectex_sample

// (offset x, offset y, scale, unused)
@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> spectex_view: vec4<f32>;

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    // Framebuffer pixel (i, j) has its centre at (i + 0.5, j + 0.5).
    let ij = in.position.xy - vec2<f32>(0.5);
    let v = spectex_sample(spectex_view.xy + ij * spectex_view.z);
    // A grey model gives f32 (splat to grey), a colour model vec3<f32>.
    return vec4<f32>(vec3<f32>(v), 1.0);
}
