#version 450
// Forward pass: albedo texture, one directional light, ambient term.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform SceneUBO {
    mat4 viewProj;
    vec4 lightDir;
    vec4 lightColor;
    vec4 cameraPos;
} scene;
layout(set = 1, binding = 0) uniform sampler2D albedoMap;

void main() {
    vec3 N = normalize(inNormal);
    vec3 L = normalize(-scene.lightDir.xyz);
    float diffuse = max(dot(N, L), 0.0);
    vec3 albedo = texture(albedoMap, inUV).rgb;
    vec3 ambient = 0.08 * albedo;
    vec3 color = ambient + diffuse * albedo * scene.lightColor.rgb;
    outColor = vec4(color, 1.0);
}
