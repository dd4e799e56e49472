#version 450
// Cel shading in three bands with a view-angle outline, colors from a specialization constant.
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inViewVec;
layout(location = 2) in vec3 inLightVec;
layout(location = 3) in vec2 inUV;
layout(location = 0) out vec4 outFragColor;

layout(constant_id = 0) const float OUTLINE = 0.25;
layout(set = 0, binding = 1) uniform sampler2D colorMap;

void main() {
    vec3 color = texture(colorMap, inUV).rgb;
    vec3 N = normalize(inNormal);
    vec3 L = normalize(inLightVec);
    vec3 V = normalize(inViewVec);
    float intensity = dot(N, L);
    float shade = intensity > 0.95 ? 1.0 : (intensity > 0.5 ? 0.7 : (intensity > 0.25 ? 0.45 : 0.25));
    float outline = step(OUTLINE, abs(dot(N, V)));
    outFragColor = vec4(color * shade * outline, 1.0);
}
