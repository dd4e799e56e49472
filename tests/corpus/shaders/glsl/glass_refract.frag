#version 450
// Glass: refraction and reflection from one cube map, chromatic dispersion by three indices.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform View {
    vec4 eye;
    vec4 tint;
} view;
layout(set = 0, binding = 1) uniform samplerCube envMap;
layout(constant_id = 0) const float IOR_R = 0.65;
layout(constant_id = 1) const float IOR_G = 0.67;
layout(constant_id = 2) const float IOR_B = 0.69;

void main() {
    vec3 I = normalize(inWorldPos - view.eye.xyz);
    vec3 N = normalize(inNormal);
    vec3 refl = texture(envMap, reflect(I, N)).rgb;
    float r = texture(envMap, refract(I, N, IOR_R)).r;
    float g = texture(envMap, refract(I, N, IOR_G)).g;
    float b = texture(envMap, refract(I, N, IOR_B)).b;
    float fresnel = clamp(0.1 + pow(1.0 + dot(I, N), 3.0), 0.0, 1.0);
    vec3 color = mix(vec3(r, g, b) * view.tint.rgb, refl, fresnel);
    outColor = vec4(color, 1.0);
}
