// GPU precomputation of the PBR tier's maps, the same algorithms as src/pbr/precompute.rs:
// one cube face per draw (uFace), direction through each texel as cube_direction does.
// MODE 0: irradiance, the cosine-weighted sum over every texel of one mip level of the
// equirectangular environment (texelFetch); MODE 1: specular, GGX samples around N = V = R
// read with textureLod at the level matching each sample's solid angle. Needs GLSL 3.30 or
// ES 3.00 (texelFetch, textureLod, uint): on GL 2.1 the CPU computes the maps.
IN vec2 vUv;
uniform sampler2D uEnv;
uniform int uFace;
uniform float uRoughness;
uniform int uSamples;
uniform float uTexelOmega;    // solid angle of a level-0 equirect texel at the equator
uniform int uLevel;           // MODE 0: the mip level summed
uniform ivec2 uLevelSize;
uniform float uMirrorLod;     // MODE 1, roughness 0: the level matching a cube texel
#include "brdf.glsl"

vec3 cubeDir(int face, vec2 uv) {
    float s = uv.x * 2.0 - 1.0;
    float t = uv.y * 2.0 - 1.0;
    vec3 d;
    if (face == 0) d = vec3(1.0, -t, -s);
    else if (face == 1) d = vec3(-1.0, -t, s);
    else if (face == 2) d = vec3(s, 1.0, t);
    else if (face == 3) d = vec3(s, -1.0, -t);
    else if (face == 4) d = vec3(s, -t, 1.0);
    else d = vec3(-s, -t, -1.0);
    return normalize(d);
}

vec2 equirect(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) / (2.0 * GLVIEW_PI), acos(clamp(d.y, -1.0, 1.0)) / GLVIEW_PI);
}

vec3 equirectDir(vec2 p, vec2 size) {
    float phi = (p.x / size.x - 0.5) * 2.0 * GLVIEW_PI;
    float theta = p.y / size.y * GLVIEW_PI;
    return vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// highp: ES fragment shaders default ints to mediump, which llvmpipe evaluates in 16 bits.
float radicalInverse(highp uint bits) {
    highp uint r = 0u;
    for (int i = 0; i < 32; ++i) {
        r = (r << 1u) | (bits & 1u);
        bits >>= 1u;
    }
    return float(r) / 4294967296.0;
}

void basis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

void main() {
    vec3 n = cubeDir(uFace, vUv);
#if MODE == 0
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int y = 0; y < uLevelSize.y; ++y) {
        float theta = (float(y) + 0.5) / float(uLevelSize.y) * GLVIEW_PI;
        float omega = sin(theta);
        for (int x = 0; x < uLevelSize.x; ++x) {
            vec3 d = equirectDir(vec2(float(x) + 0.5, float(y) + 0.5), vec2(uLevelSize));
            float c = dot(n, d);
            if (c > 0.0) {
                sum += texelFetch(uEnv, ivec2(x, y), uLevel).rgb * c * omega;
                wsum += c * omega;
            }
        }
    }
    FRAG_COLOR = vec4(sum / max(wsum, 1e-12), 1.0);
#else
    if (uRoughness <= 0.0) {
        FRAG_COLOR = vec4(textureLod(uEnv, equirect(n), max(uMirrorLod, 0.0)).rgb, 1.0);
        return;
    }
    vec3 t, b;
    basis(n, t, b);
    float a = max(uRoughness, GLVIEW_MIN_ROUGHNESS);
    a = a * a;
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int i = 0; i < uSamples; ++i) {
        float u1 = (float(i) + 0.5) / float(uSamples);
        highp uint bits = uint(i);
        float u2 = radicalInverse(bits);
        float phi = 2.0 * GLVIEW_PI * u1;
        float cosT = sqrt((1.0 - u2) / (1.0 + (a * a - 1.0) * u2));
        float sinT = sqrt(max(1.0 - cosT * cosT, 0.0));
        vec3 h = vec3(cos(phi) * sinT, sin(phi) * sinT, cosT);
        vec3 l = 2.0 * h.z * h - vec3(0.0, 0.0, 1.0);
        if (l.z > 0.0) {
            float pdf = glviewD_GGX(h.z, uRoughness) / 4.0;
            // A pdf that underflows (grazing samples of a sharp lobe) must not give an
            // infinite level: ES drivers return NaN for textureLod(..., inf).
            float omegaS = 1.0 / (float(uSamples) * max(pdf, 1e-20));
            float lod = clamp(0.5 * log2(omegaS / uTexelOmega), 0.0, 16.0);
            vec3 d = t * l.x + b * l.y + n * l.z;
            sum += textureLod(uEnv, equirect(d), lod).rgb * l.z;
            wsum += l.z;
        }
    }
    FRAG_COLOR = vec4(sum / max(wsum, 1e-12), 1.0);
#endif
}
