#version 450
// Diffuse irradiance from nine spherical-harmonic coefficients in a UBO, albedo texture.
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform SH {
    vec4 coeffs[9];
} sh;
layout(set = 1, binding = 0) uniform sampler2D albedoTex;

vec3 irradiance(vec3 n) {
    vec3 r = sh.coeffs[0].rgb * 0.886227;
    r += sh.coeffs[1].rgb * 1.023328 * n.y;
    r += sh.coeffs[2].rgb * 1.023328 * n.z;
    r += sh.coeffs[3].rgb * 1.023328 * n.x;
    r += sh.coeffs[4].rgb * 0.858086 * n.x * n.y;
    r += sh.coeffs[5].rgb * 0.858086 * n.y * n.z;
    r += sh.coeffs[6].rgb * 0.247708 * (3.0 * n.z * n.z - 1.0);
    r += sh.coeffs[7].rgb * 0.858086 * n.x * n.z;
    r += sh.coeffs[8].rgb * 0.429043 * (n.x * n.x - n.y * n.y);
    return max(r, vec3(0.0));
}

void main() {
    vec3 N = normalize(inNormal);
    vec3 albedo = texture(albedoTex, inUV).rgb;
    outColor = vec4(albedo * irradiance(N), 1.0);
}
