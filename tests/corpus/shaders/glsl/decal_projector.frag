#version 450
// Projected decal: world position into decal space, a decal texture over the surface's own albedo.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec2 inUV;
layout(location = 2) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Decal {
    mat4 worldToDecal;
    vec4 decalColor;
} decal;
layout(set = 0, binding = 1) uniform sampler2D surfaceTex;
layout(set = 0, binding = 2) uniform sampler2D decalTex;

void main() {
    vec4 d = decal.worldToDecal * vec4(inWorldPos, 1.0);
    vec2 duv = d.xy * 0.5 + 0.5;
    float inside = step(0.0, duv.x) * step(duv.x, 1.0) * step(0.0, duv.y) * step(duv.y, 1.0);
    vec4 dec = texture(decalTex, duv) * decal.decalColor;
    vec3 surface = texture(surfaceTex, inUV).rgb;
    vec3 color = mix(surface, dec.rgb, dec.a * inside);
    float light = 0.3 + 0.7 * max(normalize(inNormal).y, 0.0);
    outColor = vec4(color * light, 1.0);
}
