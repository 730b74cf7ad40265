#version 450

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec4 in_color;

layout(push_constant) uniform LinePush {
    mat4 clip_from_world;
    float depth_pull;
} push;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = in_color;
    gl_Position = push.clip_from_world * vec4(in_position, 1.0);
    gl_Position.z -= push.depth_pull * gl_Position.w;
}
