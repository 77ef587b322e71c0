// GLSL 3.30 sources of the renderer's passes.
#pragma once

namespace pbf::render::shaders {

// Colour map shared by the sphere shader (and colorMap() on the CPU side):
// piecewise linear blue -> cyan -> yellow -> red.
inline constexpr const char* kColorMap = R"(
vec3 colorMap(float t) {
    t = clamp(t, 0.0, 1.0);
    vec3 c0 = vec3(0.05, 0.20, 0.70);
    vec3 c1 = vec3(0.10, 0.70, 0.90);
    vec3 c2 = vec3(0.95, 0.90, 0.25);
    vec3 c3 = vec3(0.85, 0.15, 0.10);
    if (t < 1.0 / 3.0) return mix(c0, c1, t * 3.0);
    if (t < 2.0 / 3.0) return mix(c1, c2, t * 3.0 - 1.0);
    return mix(c2, c3, t * 3.0 - 2.0);
}
)";

// Sky seen along a world-space direction: the background and what the
// liquid reflects.
inline constexpr const char* kSky = R"(
vec3 sky(vec3 dir) {
    float y = dir.y;
    vec3 horizon = vec3(0.86, 0.90, 0.95);
    vec3 zenith = vec3(0.32, 0.52, 0.82);
    vec3 ground = vec3(0.60, 0.62, 0.66);
    if (y < 0.0) return mix(horizon, ground, clamp(-y * 3.0, 0.0, 1.0));
    return mix(horizon, zenith, pow(clamp(y, 0.0, 1.0), 0.6));
}
)";

// One camera-facing quad per particle, drawn instanced (4 vertices, one
// instance per particle): the whole fluid is one draw call.
inline constexpr const char* kSphereVertex = R"(#version 330 core
layout(location = 0) in vec4 aParticle;  // x, y, z, colour value
uniform mat4 uView;
uniform mat4 uProj;
uniform float uRadius;
uniform float uQuadScale;  // quad half-size in radii
out vec3 vViewPos;
flat out vec3 vCenter;
flat out float vValue;
void main() {
    vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
    vec4 center = uView * vec4(aParticle.xyz, 1.0);
    vCenter = center.xyz;
    vValue = aParticle.w;
    // Larger than the sphere: off the view axis its perspective outline is wider than r.
    vViewPos = center.xyz + vec3(corner * uRadius * uQuadScale, 0.0);
    gl_Position = uProj * vec4(vViewPos, 1.0);
}
)";

// Ray-sphere intersection in view space (camera at the origin): exact depth
// and normal, so the impostor is indistinguishable from a sphere mesh.
inline constexpr const char* kSphereHit = R"(
uniform mat4 uProj;
uniform float uRadius;
in vec3 vViewPos;
flat in vec3 vCenter;
flat in float vValue;
bool hitSphere(out vec3 p, out vec3 n, out float chord) {
    vec3 d = normalize(vViewPos);
    float b = dot(d, vCenter);
    float c = dot(vCenter, vCenter) - uRadius * uRadius;
    float disc = b * b - c;
    p = vec3(0.0); n = vec3(0.0, 0.0, 1.0); chord = 0.0;
    if (disc <= 0.0) return false;
    float s = sqrt(disc);
    if (b - s <= 0.0) return false;
    p = d * (b - s);
    n = (p - vCenter) / uRadius;
    chord = 2.0 * s;
    return true;
}
float windowDepth(vec3 p) {
    vec4 clip = uProj * vec4(p, 1.0);
    return clip.z / clip.w * 0.5 + 0.5;
}
)";

inline constexpr const char* kSphereShadeMain = R"(
uniform int uColorMode;  // 0 speed, 1 density, 2 flat
uniform vec2 uRange;
uniform vec3 uFlatColor;
uniform vec3 uLightView;
out vec4 outColor;
void main() {
    vec3 p, n; float chord;
    if (!hitSphere(p, n, chord)) discard;
    vec3 base = uColorMode == 2 ? uFlatColor : colorMap((vValue - uRange.x) / (uRange.y - uRange.x));
    vec3 v = -normalize(p);
    float diffuse = max(dot(n, uLightView), 0.0);
    float specular = pow(max(dot(n, normalize(uLightView + v)), 0.0), 48.0);
    outColor = vec4(base * (0.35 + 0.65 * diffuse) + vec3(0.3 * specular), 1.0);
    gl_FragDepth = windowDepth(p);
}
)";

// Liquid pass 1: the nearest sphere surface's linear depth (metres, > 0).
inline constexpr const char* kSphereDepthMain = R"(
out float outDepth;
void main() {
    vec3 p, n; float chord;
    if (!hitSphere(p, n, chord)) discard;
    outDepth = -p.z;
    gl_FragDepth = windowDepth(p);
}
)";

// Liquid pass 1 with anisotropic kernels: each particle's depth splat is
// its Yu & Turk 2013 ellipsoid (surface::computeEllipsoids, scaled to the
// splat size): flat discs along a free surface, long along a thin stream,
// spheres inside the water. One camera-facing quad per instance covering the
// ellipsoid's bounding sphere; the fragment intersects the view ray with the
// ellipsoid in its unit-sphere coordinates u = G (x - centre).
inline constexpr const char* kEllipsoidVertex = R"(#version 330 core
layout(location = 0) in vec4 aCentre;  // smoothed centre x, y, z; bounding radius
layout(location = 1) in vec3 aG0;      // rows of G (world -> unit sphere), 1/m
layout(location = 2) in vec3 aG1;
layout(location = 3) in vec3 aG2;
uniform mat4 uView;
uniform mat4 uProj;
out vec3 vViewPos;
flat out vec3 vCenter;
flat out mat3 vG;  // G in view space
void main() {
    vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
    vec4 center = uView * vec4(aCentre.xyz, 1.0);
    vCenter = center.xyz;
    // GLSL matrices are built from columns: mat3(rows) is G transposed.
    vG = transpose(mat3(aG0, aG1, aG2)) * transpose(mat3(uView));
    vViewPos = center.xyz + vec3(corner * aCentre.w * 1.5, 0.0);
    gl_Position = uProj * vec4(vViewPos, 1.0);
}
)";

inline constexpr const char* kEllipsoidDepthFragment = R"(#version 330 core
uniform mat4 uProj;
in vec3 vViewPos;
flat in vec3 vCenter;
flat in mat3 vG;
out float outDepth;
void main() {
    vec3 d = normalize(vViewPos);
    vec3 o = vG * (-vCenter);  // the camera, in the ellipsoid's unit-sphere coordinates
    vec3 e = vG * d;
    float a = dot(e, e);
    float b = dot(o, e);
    float disc = b * b - a * (dot(o, o) - 1.0);
    if (disc <= 0.0) discard;
    float t = (-b - sqrt(disc)) / a;
    if (t <= 0.0) discard;
    vec3 p = d * t;
    outDepth = -p.z;
    vec4 clip = uProj * vec4(p, 1.0);
    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;
}
)";

// White water (pbf foam's diffuse particles): small lit spheres, spray and
// foam white, bubbles a light blue-white. uDepthBias (m) moves their depth
// towards the camera, so in the liquid look foam on the smoothed surface and
// bubbles just under it are seen, and bubbles deep inside are not.
inline constexpr const char* kDiffuseMain = R"(
uniform vec3 uLightView;
uniform float uDepthBias;
out vec4 outColor;
void main() {
    vec3 p, n; float chord;
    if (!hitSphere(p, n, chord)) discard;
    int type = int(vValue + 0.5);
    vec3 base = type == 2 ? vec3(0.78, 0.88, 0.96) : (type == 1 ? vec3(0.94, 0.96, 0.98) : vec3(1.0));
    float diffuse = max(dot(n, uLightView), 0.0);
    outColor = vec4(base * (0.72 + 0.28 * diffuse), 1.0);
    gl_FragDepth = windowDepth(p * max(0.0, 1.0 - uDepthBias / max(-p.z, 1e-6)));
}
)";

// Liquid pass 2: thickness, added up over all particles (additive blending,
// no depth test). Each particle is a Gaussian splat of standard deviation
// 1.5 r in the view plane whose integral is the particle's volume (2r)^3, so
// the sum is metres of water along the ray and smooth, not dotted like a sum
// of sphere chords would be (van der Laan et al. 2009 also splat Gaussians).
inline constexpr const char* kThicknessFragment = R"(#version 330 core
uniform float uRadius;
in vec3 vViewPos;
flat in vec3 vCenter;
out float outThickness;
void main() {
    // Distance from the particle centre in its view-plane quad.
    vec2 d = (vViewPos.xy - vCenter.xy) / uRadius;
    float sigma = 1.5;
    float rho2 = dot(d, d);
    if (rho2 > 9.0 * sigma * sigma) discard;
    float amplitude = 8.0 * uRadius / (2.0 * 3.14159265 * sigma * sigma);
    outThickness = amplitude * exp(-0.5 * rho2 / (sigma * sigma));
}
)";

// A full-screen triangle from gl_VertexID (no vertex buffer).
inline constexpr const char* kFullscreenVertex = R"(#version 330 core
out vec2 vNdc;
void main() {
    vec2 p = vec2((gl_VertexID == 1) ? 3.0 : -1.0, (gl_VertexID == 2) ? 3.0 : -1.0);
    vNdc = p;
    gl_Position = vec4(p, 1.0, 1.0);
}
)";

inline constexpr const char* kSkyMain = R"(
in vec2 vNdc;
uniform mat3 uViewToWorld;
uniform vec2 uTanHalf;
out vec4 outColor;
void main() {
    vec3 dir = normalize(uViewToWorld * vec3(vNdc * uTanHalf, -1.0));
    outColor = vec4(sky(dir), 1.0);
}
)";

// The floor: a checkered plane under the domain, fading into the distance.
inline constexpr const char* kFloorVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uViewProj;
out vec3 vWorld;
void main() {
    vWorld = aPosition;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
)";

inline constexpr const char* kFloorFragment = R"(#version 330 core
in vec3 vWorld;
uniform float uTile;
uniform vec2 uCenter;
uniform float uFade;
out vec4 outColor;
void main() {
    vec2 cell = floor(vWorld.xz / uTile);
    float checker = mod(cell.x + cell.y, 2.0);
    vec3 c = mix(vec3(0.62, 0.60, 0.57), vec3(0.78, 0.76, 0.72), checker);
    float fade = clamp(length(vWorld.xz - uCenter) / uFade, 0.0, 1.0);
    outColor = vec4(mix(c, vec3(0.72, 0.75, 0.79), fade * fade), 1.0);
}
)";

// The scene's static solids: lit triangles (Lambert diffuse + ambient) in a
// neutral stone grey. The normal is turned towards the camera first, so a
// mesh with inconsistent winding is lit like a closed one.
inline constexpr const char* kSolidVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProj;
out vec3 vWorld;
out vec3 vNormal;
void main() {
    vWorld = aPosition;
    vNormal = aNormal;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
)";

inline constexpr const char* kSolidFragment = R"(#version 330 core
in vec3 vWorld;
in vec3 vNormal;
uniform vec3 uEye;         // camera position, world space
uniform vec3 uLightWorld;  // unit vector towards the light
uniform vec3 uColor;
out vec4 outColor;
void main() {
    vec3 n = normalize(vNormal);
    if (dot(n, uEye - vWorld) < 0.0) n = -n;
    float diffuse = max(dot(n, uLightWorld), 0.0);
    // Ambient brighter from above (sky) than from below (floor).
    float ambient = 0.30 + 0.10 * n.y;
    outColor = vec4(uColor * (ambient + 0.60 * diffuse), 1.0);
}
)";

inline constexpr const char* kLineFragment = R"(#version 330 core
uniform vec3 uColor;
out vec4 outColor;
void main() { outColor = vec4(uColor, 1.0); }
)";

// Liquid pass 3: smoothing of the linear depth, one 1D pass (horizontal or
// vertical). A narrow-range filter after Truong & Yuksel 2018 ("A
// Narrow-Range Filter for Screen-Space Fluid Rendering", I3D): a Gaussian
// about three splat radii wide on screen, in which samples of another surface
// far behind are left out and samples far in front are clamped to the narrow
// range around this pixel's depth, so sheets of water stay apart and lone
// drops in front do not pull the surface. Background texels (depth 0) are
// never mixed in, so the silhouette does not spread.
//
// The range test and the average are taken about the local depth *slope*
// along the pass, not about a constant depth: water seen at a grazing angle
// changes depth by more than the range from one pixel to the next, so a
// filter about a constant leaves such pixels unsmoothed in one direction and
// smoothed in the other, and the separable passes draw streaks and bands. A
// tilted plane is unchanged by this filter and the particles' bumps on it are
// smoothed as on a plane facing the camera.
inline constexpr const char* kSmoothingMain = R"(
uniform sampler2D uDepth;
uniform ivec2 uStep;            // (1, 0) horizontal pass, (0, 1) vertical pass
uniform float uPixelsPerMetre;  // at depth 1 m
uniform float uRadius;
out float outDepth;
float fetchDepth(ivec2 q) {
    return texelFetch(uDepth, clamp(q, ivec2(0), textureSize(uDepth, 0) - 1), 0).r;
}
void main() {
    ivec2 pix = ivec2(gl_FragCoord.xy);
    float z = texelFetch(uDepth, pix, 0).r;
    if (z <= 0.0) { outDepth = 0.0; return; }
    float radiusPx = clamp(uPixelsPerMetre * 3.0 * uRadius / z, 1.0, 32.0);
    float sigma = 0.5 * radiusPx;
    float range = 2.0 * uRadius;
    int n = int(ceil(radiusPx));
    // Depth slope per pixel along the pass: central difference half the
    // filter wide when both sides are the same smooth surface, else the
    // flatter one-sided difference (the other side is background or another
    // sheet of water).
    int k = max(1, n / 2);
    float za = fetchDepth(pix + k * uStep);
    float zb = fetchDepth(pix - k * uStep);
    float slope = 0.0;
    if (za > 0.0 && zb > 0.0 && abs((za - z) - (z - zb)) < 2.0 * range)
        slope = (za - zb) / float(2 * k);
    else if (za > 0.0 && (zb <= 0.0 || abs(za - z) < abs(z - zb)))
        slope = (za - z) / float(k);
    else if (zb > 0.0)
        slope = (z - zb) / float(k);
    float sum = 0.0;
    float weights = 0.0;
    for (int i = -n; i <= n; ++i) {
        float s = fetchDepth(pix + i * uStep);
        if (s <= 0.0) continue;
        // Narrow range about the local plane: another surface far behind is
        // left out; samples far in front are clamped to the range.
        float r = s - (z + slope * float(i));
        if (r > range) continue;
        r = max(r, -range);
        float w = exp(-float(i * i) / (2.0 * sigma * sigma));
        sum += r * w;
        weights += w;
    }
    outDepth = z + sum / weights;
}
)";

// Liquid pass 4: shade the smoothed surface. Normals from the depth by the
// smaller of the one-sided differences (van der Laan et al. 2009, sec. 4),
// Schlick's Fresnel mixes the reflected sky and the refracted background,
// which is offset along the normal and attenuated by exp(-absorption * thickness).
inline constexpr const char* kCompositeMain = R"(
in vec2 vNdc;
uniform sampler2D uDepth;
uniform sampler2D uThickness;
uniform sampler2D uBackground;
uniform sampler2D uBackgroundDepth;
uniform mat4 uProj;
uniform mat3 uViewToWorld;
uniform vec2 uTanHalf;
uniform vec3 uLightView;
uniform vec3 uAbsorption;   // 1/m, per colour channel
uniform vec3 uScatter;      // colour of deep water
uniform float uRefraction;  // screen offset per metre of thickness
uniform float uMinThickness;  // m: the least water any covered pixel is tinted as
out vec4 outColor;
vec3 viewPos(ivec2 pix, float z) {
    vec2 ndc = (vec2(pix) + 0.5) / vec2(textureSize(uDepth, 0)) * 2.0 - 1.0;
    return vec3(ndc * uTanHalf * z, -z);
}
vec3 derivative(ivec2 pix, vec3 p, ivec2 step) {
    ivec2 size = textureSize(uDepth, 0);
    ivec2 a = clamp(pix + step, ivec2(0), size - 1);
    ivec2 b = clamp(pix - step, ivec2(0), size - 1);
    float za = texelFetch(uDepth, a, 0).r;
    float zb = texelFetch(uDepth, b, 0).r;
    vec3 forward = za > 0.0 ? viewPos(a, za) - p : vec3(0.0);
    vec3 backward = zb > 0.0 ? p - viewPos(b, zb) : vec3(0.0);
    if (za <= 0.0) return backward;
    if (zb <= 0.0) return forward;
    return abs(forward.z) < abs(backward.z) ? forward : backward;
}
void main() {
    ivec2 pix = ivec2(gl_FragCoord.xy);
    vec2 uv = (vec2(pix) + 0.5) / vec2(textureSize(uDepth, 0));
    float z = texelFetch(uDepth, pix, 0).r;
    if (z <= 0.0) {
        outColor = vec4(texelFetch(uBackground, pix, 0).rgb, 1.0);
        gl_FragDepth = texelFetch(uBackgroundDepth, pix, 0).r;
        return;
    }
    vec3 p = viewPos(pix, z);
    vec3 dx = derivative(pix, p, ivec2(1, 0));
    vec3 dy = derivative(pix, p, ivec2(0, 1));
    vec3 n = cross(dx, dy);
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    vec3 v = -normalize(p);
    if (dot(n, v) < 0.0) n = -n;
    // The Gaussian thickness of water one particle thick (a thin stream, a
    // sheet) is about one radius: it would be all but transparent. Every
    // covered pixel is tinted as at least uMinThickness of water.
    float thickness = max(texelFetch(uThickness, pix, 0).r, uMinThickness);

    float fresnel = 0.02 + 0.98 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
    vec3 reflected = sky(uViewToWorld * reflect(-v, n));
    vec2 offset = n.xy * uRefraction * min(thickness, 0.3);
    vec3 behind = texture(uBackground, uv + offset).rgb;
    vec3 transmitted = exp(-uAbsorption * thickness);
    vec3 refracted = behind * transmitted + uScatter * (1.0 - transmitted);
    float specular = pow(max(dot(n, normalize(uLightView + v)), 0.0), 120.0);
    outColor = vec4(mix(refracted, reflected, fresnel) + vec3(0.5 * specular), 1.0);
    vec4 clip = uProj * vec4(p, 1.0);
    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;
}
)";

}  // namespace pbf::render::shaders
