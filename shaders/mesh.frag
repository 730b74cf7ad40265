#version 450

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_color;

layout(push_constant) uniform MeshPush {
    mat4 clip_from_world;
    vec4 eye;
    vec4 line_color;
    uint flags;
    float depth_pull;
} push;

layout(location = 0) out vec4 out_color;

void main() {
    if ((push.flags & 2u) != 0u) {
        out_color = push.line_color;
        return;
    }
    vec3 to_eye = normalize(push.eye.xyz - in_world);
    vec3 n = (push.flags & 1u) != 0u ? cross(dFdx(in_world), dFdy(in_world)) : in_normal;
    n = length(n) > 0.0 ? normalize(n) : to_eye;
    // Lit from both sides: meshes with open boundaries or flipped faces still read.
    if (dot(n, to_eye) < 0.0) n = -n;
    // A headlight: every visible face is lit, whatever the view.
    vec3 light = to_eye;
    float diffuse = max(dot(n, light), 0.0);
    vec3 half_vector = normalize(light + to_eye);
    float specular = pow(max(dot(n, half_vector), 0.0), 48.0) * 0.15;
    vec3 lit = in_color * (0.22 + 0.78 * diffuse) + vec3(specular);
    out_color = vec4(min(lit, vec3(1.0)), 1.0);
}
