#version 450
// Skybox: a cube map looked up along the view direction, with exposure and gamma.
layout(location = 0) in vec3 inUVW;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 1) uniform samplerCube samplerCubeMap;
layout(push_constant) uniform Params {
    layout(offset = 64) float exposure;
    float gamma;
} params;

void main() {
    vec3 color = texture(samplerCubeMap, normalize(inUVW)).rgb;
    color = vec3(1.0) - exp(-color * params.exposure);
    color = pow(color, vec3(1.0 / params.gamma));
    outColor = vec4(color, 1.0);
}
