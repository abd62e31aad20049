// The material model's sampling rules, shared by both tiers and the shadow pass
// (src/render/slots.rs sets the uniforms): each texture slot reads its own UV set through its
// KHR_texture_transform. Slots: 0 base colour, 1 metallic-roughness, 2 normal, 3 occlusion,
// 4 emissive. ALPHA_MODE: 0 opaque, 1 mask (discard below uAlphaCutoff), 2 blend (the base
// colour texture's alpha and the vertex colour's multiply the opacity), from the ALPHA_MASK /
// ALPHA_BLEND flags.
uniform mat3 uSlotXf[5];
uniform float uSlotSet[5];
uniform float uBaseAlpha;
#if defined(ALPHA_MASK)
#define ALPHA_MODE 1
#elif defined(ALPHA_BLEND)
#define ALPHA_MODE 2
#else
#define ALPHA_MODE 0
#endif
#if ALPHA_MODE == 1
uniform float uAlphaCutoff;
#endif
#ifdef HAS_UV1
IN vec2 vUv1;
#define GLVIEW_UV1 vUv1
#else
#define GLVIEW_UV1 vUv
#endif
#define SLOT_UV(i) ((uSlotXf[i] * vec3(uSlotSet[i] > 0.5 ? GLVIEW_UV1 : vUv, 1.0)).xy)

// MASK: fragments whose alpha (factor times texture) is below the cutoff are not drawn.
void glviewAlphaTest(float alpha) {
#if ALPHA_MODE == 1
    if (alpha < uAlphaCutoff) discard;
#endif
}
