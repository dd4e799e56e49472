#version 450
// Carbon-fiber weave under a clear coat: a 2x2 twill of anisotropic tows (the highlight runs along
// each tow, which turns 90 degrees from one to the next), a GGX clear coat reflecting a cube map,
// and up to four point lights from an array of structs in a uniform block, the count a
// specialization constant.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 3) in vec4 inTangent;
layout(location = 0) out vec4 outColor;

struct PointLight {
    vec4 position;   // w unused
    vec4 color;      // rgb color, a intensity
};

layout(set = 0, binding = 0) uniform Frame {
    vec3 camera_pos;
    float time;
    PointLight lights[4];
    vec4 fiberColor;
    float weaveScale;
    float coatRoughness;
    float fiberShininess;
    float envIntensity;
} frame;

layout(set = 1, binding = 0) uniform samplerCube envCube;

layout(constant_id = 0) const int LIGHT_COUNT = 3;
layout(constant_id = 1) const float COAT_F0 = 0.04;

const float PI = 3.14159265;

float ggx(float NdotH, float a) {
    float a2 = a * a;
    float d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Twill: which way the tow runs here (0: along u, 1: along v) and the tow's cross profile.
vec2 twill(vec2 uv) {
    vec2 p = uv * frame.weaveScale;
    vec2 cell = floor(p);
    float dir = mod(floor((cell.x + cell.y) * 0.5), 2.0);
    vec2 f = fract(p);
    float across = dir < 0.5 ? f.y : f.x;
    float profile = sin(across * PI);
    return vec2(dir, profile);
}

void main() {
    vec3 N = normalize(inNormal);
    vec3 T = normalize(inTangent.xyz - N * dot(N, inTangent.xyz));
    vec3 B = cross(N, T) * inTangent.w;
    vec3 V = normalize(frame.camera_pos - inWorldPos);

    vec2 tw = twill(inUV);
    vec3 tow = tw.x < 0.5 ? T : B;
    vec3 fiber = frame.fiberColor.rgb * (0.6 + 0.4 * tw.y);

    vec3 color = vec3(0.0);
    for (int i = 0; i < LIGHT_COUNT; i++) {
        vec3 toLight = frame.lights[i].position.xyz - inWorldPos;
        float dist2 = dot(toLight, toLight);
        vec3 L = toLight * inversesqrt(dist2);
        vec3 radiance = frame.lights[i].color.rgb * frame.lights[i].color.a / (1.0 + dist2);
        float NdotL = max(dot(N, L), 0.0);
        vec3 H = normalize(L + V);
        // Kajiya-Kay along the tow.
        float TdotH = dot(tow, H);
        float aniso = pow(sqrt(max(1.0 - TdotH * TdotH, 0.0)), frame.fiberShininess) * tw.y;
        float coat = ggx(max(dot(N, H), 0.0), frame.coatRoughness) * 0.25;
        color += (fiber * NdotL * 0.3 + fiber * aniso * NdotL + vec3(coat * COAT_F0) * NdotL) * radiance;
    }

    float NdotV = max(dot(N, V), 1e-3);
    float F = COAT_F0 + (1.0 - COAT_F0) * pow(1.0 - NdotV, 5.0);
    vec3 R = reflect(-V, N);
    vec3 env = textureLod(envCube, R, frame.coatRoughness * 6.0).rgb * frame.envIntensity;
    color = color * (1.0 - F) + env * F;
    outColor = vec4(color / (1.0 + color), 1.0);
}
