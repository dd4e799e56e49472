#version 450
// Cheap subsurface scattering: wrapped diffuse, a thickness map for back-lit transmission.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Light {
    vec4 position;
    vec4 color;
    vec4 cameraPos;
    vec4 subsurfaceColor;
} light;
layout(set = 1, binding = 0) uniform sampler2D skinAlbedo;
layout(set = 1, binding = 1) uniform sampler2D thicknessMap;
layout(constant_id = 0) const float WRAP = 0.5;

void main() {
    vec3 N = normalize(inNormal);
    vec3 L = normalize(light.position.xyz - inWorldPos);
    vec3 V = normalize(light.cameraPos.xyz - inWorldPos);
    float wrapped = max((dot(N, L) + WRAP) / (1.0 + WRAP), 0.0);
    float thickness = texture(thicknessMap, inUV).r;
    float back = pow(clamp(dot(V, -L), 0.0, 1.0), 4.0) * (1.0 - thickness);
    vec3 albedo = texture(skinAlbedo, inUV).rgb;
    vec3 color = albedo * wrapped * light.color.rgb + light.subsurfaceColor.rgb * back;
    outColor = vec4(color, 1.0);
}
