#version 450
// Shadow map with a 3x3 percentage-closer filter (depth compared by hand), Lambert light.
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inColor;
layout(location = 2) in vec3 inLightVec;
layout(location = 3) in vec4 inShadowCoord;
layout(location = 0) out vec4 outFragColor;

layout(binding = 1) uniform sampler2D shadowMap;
layout(constant_id = 0) const int enablePCF = 1;
layout(constant_id = 1) const float ambient = 0.1;

float textureProjShadow(vec4 shadowCoord, vec2 off) {
    float dist = texture(shadowMap, shadowCoord.st + off).r;
    return (shadowCoord.w > 0.0 && dist < shadowCoord.z - 0.005) ? ambient : 1.0;
}

void main() {
    vec4 sc = inShadowCoord / inShadowCoord.w;
    vec2 texel = 1.0 / vec2(textureSize(shadowMap, 0));
    float shadow = textureProjShadow(sc, vec2(0.0));
    if (enablePCF == 1) {
        shadow = 0.0;
        for (int x = -1; x <= 1; x++) {
            for (int y = -1; y <= 1; y++) {
                shadow += textureProjShadow(sc, vec2(x, y) * texel);
            }
        }
        shadow /= 9.0;
    }
    vec3 N = normalize(inNormal);
    vec3 L = normalize(inLightVec);
    vec3 diffuse = max(dot(N, L), ambient) * inColor;
    outFragColor = vec4(diffuse * shadow, 1.0);
}
