#version 450
// Editor-style debug grid on world geometry: anti-aliased lines from fwidth at several levels (each
// ten times finer), colored X and Z axes, an optional checker under them, faded with distance from
// the camera and lit by a head light so the shape still reads. The number of levels and the checker
// are specialization constants.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Grid {
    vec3 camera_pos;
    float time;
    vec4 lineColor;
    vec4 surfaceColor;
    vec4 axisXColor;
    vec4 axisZColor;
    float cellSize;
    float lineWidth;
    float fadeDistance;
    float checkerContrast;
} grid;

layout(constant_id = 0) const int GRID_LEVELS = 2;
layout(constant_id = 1) const bool SHOW_CHECKER = true;

// Coverage of the grid lines of one cell size, one pixel wide scaled by lineWidth.
float gridLines(vec2 p, float cell) {
    vec2 coord = p / cell;
    vec2 w = fwidth(coord) * grid.lineWidth;
    vec2 g = abs(fract(coord - 0.5) - 0.5) / max(w, vec2(1e-5));
    float line = 1.0 - min(min(g.x, g.y), 1.0);
    // Fade a level out before its lines merge into grey.
    float density = max(w.x, w.y);
    return line * (1.0 - smoothstep(0.1, 0.5, density));
}

void main() {
    vec3 N = normalize(inNormal);
    // Project onto the plane the normal faces most.
    vec3 an = abs(N);
    vec2 p = an.y > max(an.x, an.z) ? inWorldPos.xz : (an.x > an.z ? inWorldPos.zy : inWorldPos.xy);

    vec3 color = grid.surfaceColor.rgb;
    if (SHOW_CHECKER) {
        vec2 c = floor(p / grid.cellSize);
        float checker = mod(c.x + c.y, 2.0);
        color *= 1.0 - grid.checkerContrast * checker;
    }

    float lines = 0.0;
    float cell = grid.cellSize;
    for (int i = 0; i < GRID_LEVELS; i++) {
        lines = max(lines, gridLines(p, cell) * (1.0 - 0.35 * float(i)));
        cell *= 0.1;
    }
    color = mix(color, grid.lineColor.rgb, lines * grid.lineColor.a);

    // Axes through the origin.
    vec2 pw = fwidth(inWorldPos.xz) * grid.lineWidth * 1.5;
    float axisX = 1.0 - min(abs(inWorldPos.z) / max(pw.y, 1e-5), 1.0);
    float axisZ = 1.0 - min(abs(inWorldPos.x) / max(pw.x, 1e-5), 1.0);
    // Only on floors: walls keep their grid.
    float floorMask = an.y > max(an.x, an.z) ? 1.0 : 0.0;
    color = mix(color, grid.axisXColor.rgb, axisX * floorMask);
    color = mix(color, grid.axisZColor.rgb, axisZ * floorMask);

    // Head light and distance fade.
    vec3 V = normalize(grid.camera_pos - inWorldPos);
    float shade = 0.35 + 0.65 * max(dot(N, V), 0.0);
    float fade = 1.0 - smoothstep(grid.fadeDistance * 0.5, grid.fadeDistance, length(grid.camera_pos - inWorldPos));
    outColor = vec4(mix(grid.surfaceColor.rgb * 0.5, color * shade, fade), 1.0);
}
