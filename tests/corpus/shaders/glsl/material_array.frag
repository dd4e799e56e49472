#version 450
// Bindless-style material: an array of combined samplers indexed by a push-constant material id.
layout(location = 0) in vec2 inUV;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2D textures[4];
layout(push_constant) uniform Material {
    layout(offset = 64) int albedoIndex;
    layout(offset = 68) int emissiveIndex;
    layout(offset = 80) vec4 tint;
} material;

void main() {
    vec3 albedo = texture(textures[material.albedoIndex], inUV).rgb * material.tint.rgb;
    vec3 emissive = texture(textures[material.emissiveIndex], inUV).rgb;
    float light = 0.2 + 0.8 * max(dot(normalize(inNormal), normalize(vec3(0.3, 1.0, 0.2))), 0.0);
    outColor = vec4(albedo * light + emissive, 1.0);
}
