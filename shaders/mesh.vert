#version 450

// One streamed vertex: position, smooth normal and the highlight mark.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in uint in_mark;

layout(push_constant) uniform MeshPush {
    mat4 clip_from_world;
    vec4 eye;          // xyz: camera position
    vec4 line_color;   // the wireframe's colour
    uint flags;        // 1: flat shading, 2: this pass draws the wireframe
    float depth_pull;  // clip-space z pulled towards the eye (wireframe over its surface)
} push;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_color;

const vec3 mark_colors[4] = vec3[4](
    vec3(0.78, 0.76, 0.72),   // normal surface
    vec3(0.90, 0.08, 0.06),   // ROI
    vec3(0.10, 0.80, 0.15),   // handle
    vec3(0.30, 0.45, 0.85));  // fixed part

void main() {
    out_world = in_position;
    out_normal = in_normal;
    out_color = mark_colors[min(in_mark, 3u)];
    gl_Position = push.clip_from_world * vec4(in_position, 1.0);
    gl_Position.z -= push.depth_pull * gl_Position.w;
}
