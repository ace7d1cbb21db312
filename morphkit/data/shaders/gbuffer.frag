#version 330 core
// morphkit: a copy of pyrender's flat.frag (pyrender 0.1.45 / pyrender2 0.2.2,
// MIT licence, Copyright (c) 2019 Matthew Matl; see LICENSE-pyrender.txt here)
// changed where marked "morphkit:" (see morphkit/render.py, "Materials" and "One-pass frame and G-buffer").
// morphkit: the G-buffer: flat.frag's albedo and normals.frag's encoded normal
// from one draw, into two colour attachments.
///////////////////////////////////////////////////////////////////////////////
// Structs
///////////////////////////////////////////////////////////////////////////////

struct Material {
    vec3 emissive_factor;

#ifdef USE_METALLIC_MATERIAL
    vec4 base_color_factor;
    float metallic_factor;
    float roughness_factor;
#endif

#ifdef USE_GLOSSY_MATERIAL
    vec4 diffuse_factor;
    vec3 specular_factor;
    float glossiness_factor;
#endif

#ifdef HAS_NORMAL_TEX
    sampler2D normal_texture;
#endif
#ifdef HAS_OCCLUSION_TEX
    sampler2D occlusion_texture;
#endif
#ifdef HAS_EMISSIVE_TEX
    sampler2D emissive_texture;
#endif
#ifdef HAS_BASE_COLOR_TEX
    sampler2D base_color_texture;
#endif
#ifdef HAS_METALLIC_ROUGHNESS_TEX
    sampler2D metallic_roughness_texture;
#endif
#ifdef HAS_DIFFUSE_TEX
    sampler2D diffuse_texture;
#endif
#ifdef HAS_SPECULAR_GLOSSINESS_TEX
    sampler2D specular_glossiness;
#endif
};

///////////////////////////////////////////////////////////////////////////////
// Uniforms
///////////////////////////////////////////////////////////////////////////////
uniform Material material;
uniform vec3 cam_pos;

#ifdef USE_IBL
uniform samplerCube diffuse_env;
uniform samplerCube specular_env;
#endif

///////////////////////////////////////////////////////////////////////////////
// Inputs
///////////////////////////////////////////////////////////////////////////////

in vec3 frag_position;
#ifdef NORMAL_LOC
in vec3 frag_normal;
#endif
#ifdef HAS_NORMAL_TEX
#ifdef TANGENT_LOC
#ifdef NORMAL_LOC
in mat3 tbn;
#endif
#endif
#endif
#ifdef TEXCOORD_0_LOC
in vec2 uv_0;
#endif
#ifdef TEXCOORD_1_LOC
in vec2 uv_1;
#endif
#ifdef COLOR_0_LOC
in vec4 color_multiplier;
#endif

///////////////////////////////////////////////////////////////////////////////
// OUTPUTS
///////////////////////////////////////////////////////////////////////////////

layout(location = 0) out vec4 frag_color;  // morphkit: the albedo (flat.frag's)
layout(location = 1) out vec4 frag_normal_code;  // morphkit: the encoded normal (normals.frag's)

///////////////////////////////////////////////////////////////////////////////
// Constants
///////////////////////////////////////////////////////////////////////////////
const float PI = 3.141592653589793;
const float min_roughness = 0.04;

///////////////////////////////////////////////////////////////////////////////
// Utility Functions
///////////////////////////////////////////////////////////////////////////////
vec4 srgb_to_linear(vec4 srgb)
{
#ifndef SRGB_CORRECTED
    // Fast Approximation
    //vec3 linOut = pow(srgbIn.xyz,vec3(2.2));
    //
    vec3 b_less = step(vec3(0.04045),srgb.xyz);
    vec3 lin_out = mix( srgb.xyz/vec3(12.92), pow((srgb.xyz+vec3(0.055))/vec3(1.055),vec3(2.4)), b_less );
    return vec4(lin_out, srgb.w);
#else
    return srgb;
#endif
}

// morphkit: the exact sRGB encoding (the albedo pass writes sRGB-encoded base colour)
vec4 linear_to_srgb(vec4 lin)
{
    vec3 c = clamp(lin.xyz, 0.0, 1.0);
    vec3 b_less = step(vec3(0.0031308), c);
    vec3 srgb_out = mix(c * vec3(12.92), vec3(1.055) * pow(c, vec3(1.0 / 2.4)) - vec3(0.055), b_less);
    return vec4(srgb_out, lin.w);
}

///////////////////////////////////////////////////////////////////////////////
// MAIN
///////////////////////////////////////////////////////////////////////////////
void main()
{

    // Compute albedo
    // morphkit: in linear light, as mesh.frag lights it: the factor is linear, texels and
    // vertex colours are sRGB-encoded and decoded here; the result is encoded below.
    vec4 base_color = material.base_color_factor;
#ifdef HAS_BASE_COLOR_TEX
    base_color = base_color * srgb_to_linear(texture(material.base_color_texture, uv_0));
#endif

#ifdef COLOR_0_LOC
    base_color *= srgb_to_linear(color_multiplier);
#endif

    // morphkit: cut-out texels are holes. A look without a cutoff has every alpha at 1;
    // one with cutoff c has its factor alpha scaled by 0.5 / c, so this one test is
    // glTF's alpha < alphaCutoff.
    if (base_color.a < 0.5) {
        discard;
    }
    // morphkit: sRGB-encoded, like every colour image (a texel comes out as itself)
    frag_color = clamp(linear_to_srgb(base_color), 0.0, 1.0);
    // morphkit: the world-frame unit normal of the side facing the camera, encoded
    // (127 n + 128) / 255: 0 and +-1 are exact 8-bit levels (as normals.frag)
#ifdef NORMAL_LOC
    vec3 n = normalize(frag_normal);
#else
    vec3 n = normalize(cross(dFdx(frag_position), dFdy(frag_position)));
#endif
    if (!gl_FrontFacing) {
        n = -n;
    }
    frag_normal_code = vec4(clamp((127.0 * n + 128.0) / 255.0, 0.0, 1.0), 1.0);
}
