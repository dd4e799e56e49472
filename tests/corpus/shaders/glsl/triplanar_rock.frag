#version 450
// Triplanar mapping of one texture, weights from the world normal.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

layout(set = 1, binding = 0) uniform sampler2D rockTex;
layout(push_constant) uniform Push {
    layout(offset = 0) vec4 lightDir;
    layout(offset = 16) float texScale;
    layout(offset = 20) float sharpness;
} pc;

vec3 triplanar(sampler2D tex, vec3 p, vec3 n) {
    vec3 w = pow(abs(n), vec3(pc.sharpness));
    w /= (w.x + w.y + w.z);
    vec3 x = texture(tex, p.yz * pc.texScale).rgb;
    vec3 y = texture(tex, p.xz * pc.texScale).rgb;
    vec3 z = texture(tex, p.xy * pc.texScale).rgb;
    return x * w.x + y * w.y + z * w.z;
}

void main() {
    vec3 N = normalize(inNormal);
    vec3 albedo = triplanar(rockTex, inWorldPos, N);
    float ndl = max(dot(N, -pc.lightDir.xyz), 0.0);
    outColor = vec4(albedo * (0.15 + ndl), 1.0);
}
