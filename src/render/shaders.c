/* GLSL 3.30 sources of the renderer and the helpers that compile and link them.
 *
 * Index: mesh vertex stage (skinning, normals and tangents through the cofactor, heat
 * weight, Gouraud lighting) - surface effects (environment lookups, shadows, occlusion, tone
 * mapping) - physically based shading - mesh fragment stage (materials, heat map,
 * flat/Gouraud/Phong/PBR, sRGB out) - normals geometry stage (a line per vertex) - overlay
 * stages (coloured lines, points, triangles, text) - background, ground and outline passes -
 * compile/link.
 */
#include <stdio.h>
#include <string.h>

#include "internal.h"

/* Lighting shared by the vertex (Gouraud) and fragment (flat, Phong) stages: a key and a
 * fill light fixed to the camera, a sky/ground ambient, and a mild Blinn-Phong highlight.
 * Works in linear RGB. */
static const char *const LIGHTING =
    "uniform vec3 u_key_dir;   // towards the key light, world space\n"
    "uniform vec3 u_fill_dir;  // towards the fill light\n"
    "uniform vec3 u_eye;\n"
    "// key_light: how much of the key light reaches p (shadows: 0..1)\n"
    "void light_terms(vec3 n, vec3 p, float key_light, out vec3 diffuse, out vec3 specular) {\n"
    "    vec3 v = normalize(u_eye - p);\n"
    "    float hemi = 0.5 + 0.5 * n.y;\n"
    "    vec3 ambient = mix(vec3(0.10, 0.09, 0.08), vec3(0.20, 0.22, 0.26), hemi);\n"
    "    float key = max(dot(n, u_key_dir), 0.0) * key_light;\n"
    "    float fill = max(dot(n, u_fill_dir), 0.0);\n"
    "    diffuse = ambient + key * vec3(0.85, 0.82, 0.78) + fill * vec3(0.25, 0.28, 0.33);\n"
    "    vec3 h = normalize(u_key_dir + v);\n"
    "    specular = key > 0.0 ? vec3(0.18) * pow(max(dot(n, h), 0.0), 32.0) : vec3(0.0);\n"
    "}\n";

/* The mesh vertex shader: inputs, uniforms and the skinning functions, then main(). */
static const char *const MESH_VS_HEAD =
    "layout(location = 0) in vec3 a_position;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "layout(location = 3) in uvec4 a_joints0;\n"
    "layout(location = 4) in uvec4 a_joints1;\n"
    "layout(location = 5) in vec4 a_weights0;\n"
    "layout(location = 6) in vec4 a_weights1;\n"
    "layout(location = 7) in vec4 a_tangent;       // xyz, handedness; 0 when the mesh has none\n"
    "layout(location = 8) in float a_dq_weight;    // mixed skinning: this vertex's share of DQS\n"
    "layout(location = 9) in vec4 a_color;         // linear RGBA times the base colour; 1 without\n"
    "uniform mat4 u_model;          // rigid or CPU-skinned: vertices to world\n"
    "uniform mat4 u_view_proj;\n"
    "uniform int u_gpu_sets;        // 0: no GPU skinning; 1: 4 influences; 2: 8\n"
    "uniform int u_dq_mode;         // 0: linear blend; 1: dual quaternions; 2: both, by a_dq_weight\n"
    "uniform int u_dq_offset;       // records from a joint's matrix to its sinew_dq_joint record\n"
    "uniform int u_palette_offset;  // first matrix of this skin in u_palette\n"
    "uniform int u_instance_stride; // records a crowd character takes in u_palette (0: one character)\n"
    "uniform int u_rigid_record;    // >= 0: a rigid mesh's world matrix is this record of the character\n"
    "uniform int u_instance_base;   // the first crowd character of this draw\n"
    "uniform samplerBuffer u_palette;\n"
    "// Morph targets: the mesh's offsets, target after target, vertex after vertex (u_morph_texels\n"
    "// texels each: the position's, then the normal's), and the targets with weight this draw.\n"
    "uniform samplerBuffer u_morph;\n"
    "uniform int u_morph_count;\n"
    "uniform int u_morph_vertices;\n"
    "uniform int u_morph_texels;\n"
    "uniform int u_morph_target[16];\n"
    "uniform float u_morph_weight[16];\n"
    "uniform int u_heat_joint;      // skin-local joint index, -1 for none\n"
    "uniform float u_heat_rigid;    // weight of rigid meshes (1 when at the joint)\n"
    "uniform bool u_gouraud;\n"
    "out vec3 v_world;\n"
    "out vec3 v_normal;\n"
    "out vec4 v_tangent;\n"
    "out vec2 v_uv;\n"
    "out vec4 v_color;\n"
    "out float v_heat;\n"
    "out vec3 v_diffuse;\n"
    "out vec3 v_specular;\n"
    "mat4 record_matrix(int record) {\n"
    "    int base = ((u_instance_base + gl_InstanceID) * u_instance_stride + record) * 4;\n"
    "    return mat4(texelFetch(u_palette, base), texelFetch(u_palette, base + 1),\n"
    "                texelFetch(u_palette, base + 2), texelFetch(u_palette, base + 3));\n"
    "}\n"
    "mat4 joint_matrix(uint j) {\n"
    "    return record_matrix(u_palette_offset + int(j));\n"
    "}\n"
    "// Dual-quaternion skinning (as sinew_skin_vertices): blended scale/shear S, then the\n"
    "// blended unit dual quaternion; each joint's quaternion in the first one's hemisphere.\n"
    "vec4 dq_real0;\n"
    "int dq_base(uint j) {\n"
    "    return ((u_instance_base + gl_InstanceID) * u_instance_stride + u_dq_offset + u_palette_offset + int(j)) * "
    "4;\n"
    "}\n"
    "void dq_add(uint j, float w, inout vec4 real, inout vec4 dual, inout vec4 s0, inout vec4 s1) {\n"
    "    int base = dq_base(j);\n"
    "    vec4 r = texelFetch(u_palette, base);\n"
    "    float wq = dot(r, dq_real0) < 0.0 ? -w : w;\n"
    "    real += wq * r;\n"
    "    dual += wq * texelFetch(u_palette, base + 1);\n"
    "    s0 += w * texelFetch(u_palette, base + 2);\n"
    "    s1 += w * texelFetch(u_palette, base + 3);\n"
    "}\n"
    "vec3 dq_rotate(vec4 q, vec3 v) {\n"
    "    return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v);\n"
    "}\n"
    "float heat_of(uvec4 j, vec4 w) {\n"
    "    uint h = uint(u_heat_joint);\n"
    "    return dot(w, vec4(equal(j, uvec4(h))));\n"
    "}\n";

static const char *const MESH_VS =
    "// Everything after the vertex's world position and v_normal.\n"
    "void finish(vec3 world) {\n"
    "    v_world = world;\n"
    "    v_uv = a_uv;\n"
    "    v_color = a_color;\n"
    "    v_heat = u_heat_joint < 0 ? u_heat_rigid : heat_of(a_joints0, a_weights0) + heat_of(a_joints1, a_weights1);\n"
    "    v_diffuse = vec3(1.0);\n"
    "    v_specular = vec3(0.0);\n"
    "    if (u_gouraud)\n"
    "        light_terms(v_normal, v_world, 1.0, v_diffuse, v_specular);\n"
    "    gl_Position = u_view_proj * vec4(world, 1.0);\n"
    "}\n"
    "// The vertex by dual quaternions: world position, normal.\n"
    "void skin_dq(vec3 p, vec3 nin, out vec3 world, out vec3 n) {\n"
    "    dq_real0 = texelFetch(u_palette, dq_base(a_joints0.x));\n"
    "    vec4 real = vec4(0.0), dual = vec4(0.0), s0 = vec4(0.0), s1 = vec4(0.0);\n"
    "    for (int i = 0; i < 4; i++) dq_add(a_joints0[i], a_weights0[i], real, dual, s0, s1);\n"
    "    if (u_gpu_sets > 1)\n"
    "        for (int i = 0; i < 4; i++) dq_add(a_joints1[i], a_weights1[i], real, dual, s0, s1);\n"
    "    float len = length(real);\n"
    "    real /= len;\n"
    "    dual /= len;\n"
    "    mat3 s = mat3(s0.x, s0.w, s1.x, s0.w, s0.y, s1.y, s1.x, s1.y, s0.z); // xx yy zz xy | xz yz\n"
    "    vec3 t = 2.0 * (real.w * dual.xyz - dual.w * real.xyz + cross(real.xyz, dual.xyz));\n"
    "    world = dq_rotate(real, s * p) + t;\n"
    "    mat3 cof = mat3(cross(s[1], s[2]), cross(s[2], s[0]), cross(s[0], s[1]));\n"
    "    float side = dot(s[0], cof[0]) < 0.0 ? -1.0 : 1.0;\n"
    "    n = dq_rotate(real, side * (cof * nin));\n"
    "}\n"
    "void main() {\n"
    "    // morph targets first, in the mesh's space (only those with weight were given)\n"
    "    vec3 p = a_position, nin = a_normal;\n"
    "    for (int i = 0; i < u_morph_count; i++) {\n"
    "        int base = (u_morph_target[i] * u_morph_vertices + gl_VertexID) * u_morph_texels;\n"
    "        p += u_morph_weight[i] * texelFetch(u_morph, base).xyz;\n"
    "        if (u_morph_texels > 1)\n"
    "            nin += u_morph_weight[i] * texelFetch(u_morph, base + 1).xyz;\n"
    "    }\n"
    "    mat4 m = u_rigid_record >= 0 ? record_matrix(u_rigid_record) : u_model;\n"
    "    float dq = u_gpu_sets > 0 ? (u_dq_mode == 1 ? 1.0 : u_dq_mode == 2 ? a_dq_weight : 0.0) : 0.0;\n"
    "    vec3 dq_world = vec3(0.0), dq_n = vec3(0.0);\n"
    "    if (dq > 0.0)\n"
    "        skin_dq(p, nin, dq_world, dq_n);\n"
    "    if (dq >= 1.0) {\n"
    "        float nlen = length(dq_n);\n"
    "        v_normal = nlen > 0.0 ? dq_n / nlen : vec3(0.0, 1.0, 0.0);\n"
    "        finish(dq_world);\n"
    "        return;\n"
    "    }\n"
    "    if (u_gpu_sets > 0) {\n"
    "        m = a_weights0.x * joint_matrix(a_joints0.x) + a_weights0.y * joint_matrix(a_joints0.y)\n"
    "          + a_weights0.z * joint_matrix(a_joints0.z) + a_weights0.w * joint_matrix(a_joints0.w);\n"
    "        if (u_gpu_sets > 1)\n"
    "            m += a_weights1.x * joint_matrix(a_joints1.x) + a_weights1.y * joint_matrix(a_joints1.y)\n"
    "               + a_weights1.z * joint_matrix(a_joints1.z) + a_weights1.w * joint_matrix(a_joints1.w);\n"
    "    }\n"
    "    vec4 world = m * vec4(p, 1.0);\n"
    "    mat3 a = mat3(m);\n"
    "    mat3 cof = mat3(cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1]));\n"
    "    float side = dot(a[0], cof[0]) < 0.0 ? -1.0 : 1.0;\n"
    "    vec3 n = side * (cof * nin);\n"
    "    float len = length(n);\n"
    "    n = len > 0.0 ? n / len : vec3(0.0, 1.0, 0.0);\n"
    "    if (dq > 0.0) { // mixed: (1 - a) linear + a dual quaternion\n"
    "        float dlen = length(dq_n);\n"
    "        world.xyz = mix(world.xyz, dq_world, dq);\n"
    "        n = normalize(mix(n, dlen > 0.0 ? dq_n / dlen : n, dq));\n"
    "    }\n"
    "    v_normal = n;\n"
    "    v_tangent = vec4(a * a_tangent.xyz, side * a_tangent.w);\n"
    "    finish(world.xyz);\n"
    "}\n";

/* Physically based shading as glTF defines it (metallic-roughness, Cook-Torrance with GGX,
 * Smith-GGX visibility and Schlick Fresnel): the key and fill lights (the built-in studio
 * only) plus image-based lighting, its diffuse part the environment's irradiance (spherical
 * harmonics) and its specular part the split-sum approximation (the prefiltered level of the
 * roughness along the reflection, times the BRDF table's scale and bias of F0). Linear out:
 * MESH_FS applies exposure and tone mapping. */
/* The mesh fragment stage's inputs, before PBR and MESH_FS, which read them. */
static const char *const MESH_FS_INPUTS = "in vec3 v_world;\n"
                                          "in vec3 v_normal;\n"
                                          "in vec4 v_tangent;\n"
                                          "in vec2 v_uv;\n"
                                          "in vec4 v_color;\n"
                                          "in float v_heat;\n"
                                          "in vec3 v_diffuse;\n"
                                          "in vec3 v_specular;\n";

/* What the fragment stages of surfaces share (meshes and the ground): the environment's
 * lookups, shadows from the shadow map, screen-space ambient occlusion from the depth pre-pass,
 * exposure and tone mapping. */
static const char *const EFFECTS =
    "#define ENV_LEVELS 6\n"
    "uniform sampler2D u_env;         // equirectangular, RGB16F, ENV_LEVELS prefiltered levels\n"
    "uniform sampler2D u_brdf;        // split-sum table: x n.v, y roughness\n"
    "uniform vec3 u_sh[9];            // irradiance / pi as spherical harmonics\n"
    "uniform float u_env_direct;      // 1: the key and fill lights too (studio); 0: the environment alone\n"
    "uniform sampler2DShadow u_shadow_map;\n"
    "uniform mat4 u_shadow_matrix;    // world to the shadow map's [0,1] cube\n"
    "uniform float u_shadow_strength; // 0: no shadows\n"
    "uniform float u_shadow_bias;     // world units along the normal\n"
    "uniform sampler2D u_depth;       // the depth pre-pass (occlusion)\n"
    "uniform float u_ao_radius;       // world units\n"
    "uniform mat4 u_inv_view_proj;\n"
    "uniform mat4 u_ao_view_proj;\n"
    "uniform vec2 u_viewport;\n"
    "uniform float u_exposure;        // linear scale\n"
    "uniform int u_tone;              // 0 none, 1 ACES, 2 Khronos PBR Neutral\n"
    "vec2 env_uv(vec3 d) {\n"
    "    d = normalize(d);\n"
    "    return vec2(0.5 + atan(d.x, -d.z) * 0.15915494, acos(clamp(d.y, -1.0, 1.0)) * 0.31830989);\n"
    "}\n"
    "vec3 env_radiance(vec3 d, float lod) {\n"
    "    return textureLod(u_env, env_uv(d), lod).rgb;\n"
    "}\n"
    "vec3 env_irradiance(vec3 n) {\n"
    "    vec3 r = u_sh[0] * 0.282095 + (u_sh[1] * n.y + u_sh[2] * n.z + u_sh[3] * n.x) * 0.488603\n"
    "           + (u_sh[4] * n.x * n.y + u_sh[5] * n.y * n.z + u_sh[7] * n.x * n.z) * 1.092548\n"
    "           + u_sh[6] * 0.315392 * (3.0 * n.z * n.z - 1.0) + u_sh[8] * 0.546274 * (n.x * n.x - n.y * n.y);\n"
    "    return max(r, vec3(0.0));\n"
    "}\n"
    "#ifdef WITH_SHADOWS\n"
    "float shadow_visibility(vec3 p, vec3 n) {\n"
    "    vec4 s = u_shadow_matrix * vec4(p + n * u_shadow_bias, 1.0);\n"
    "    s.xyz /= s.w;\n"
    "    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;\n"
    "    // four bilinear comparisons (16 texels) a texel apart\n"
    "    vec2 t = 0.5 / vec2(textureSize(u_shadow_map, 0));\n"
    "    float z = min(s.z, 1.0);\n"
    "    float lit = texture(u_shadow_map, vec3(s.xy + vec2(-t.x, -t.y), z)) + texture(u_shadow_map, vec3(s.xy + "
    "vec2(t.x, -t.y), z))\n"
    "              + texture(u_shadow_map, vec3(s.xy + vec2(-t.x, t.y), z)) + texture(u_shadow_map, vec3(s.xy + t, "
    "z));\n"
    "    return 1.0 - u_shadow_strength * (1.0 - 0.25 * lit);\n"
    "}\n"
    "#else\n"
    "float shadow_visibility(vec3 p, vec3 n) { return 1.0; }\n"
    "#endif\n";

/* Screen-space ambient occlusion, exposure, tone mapping and sRGB. */
static const char *const EFFECTS_POST =
    "// Occlusion of the hemisphere around n at p by the depth pre-pass's surfaces: 12 points on a\n"
    "// spiral within u_ao_radius on screen, each counting by its cosine to n and fading with distance.\n"
    "#ifdef WITH_AO\n"
    "float ambient_occlusion(vec3 p, vec3 n) {\n"
    "    vec4 c = u_ao_view_proj * vec4(p, 1.0);\n"
    "    if (c.w <= 0.0) return 1.0;\n"
    "    vec2 px = gl_FragCoord.xy;\n"
    "    vec4 e = u_ao_view_proj * vec4(p + u_ao_radius * normalize(cross(n, vec3(0.577, 0.577, 0.577)) + 1e-6), "
    "1.0);\n"
    "    float radius = clamp(length(e.xy / e.w - c.xy / c.w) * 0.5 * max(u_viewport.x, u_viewport.y), 2.0, 96.0);\n"
    "    float noise = fract(52.9829189 * fract(dot(px, vec2(0.06711056, 0.00583715))));\n"
    "    float occluded = 0.0;\n"
    "    for (int i = 0; i < 12; i++) {\n"
    "        float a = (float(i) + noise) * 2.3999632;\n"
    "        float rr = radius * sqrt((float(i) + 0.5) / 12.0);\n"
    "        vec2 q = (px + rr * vec2(cos(a), sin(a))) / u_viewport;\n"
    "        if (any(lessThan(q, vec2(0.0))) || any(greaterThan(q, vec2(1.0)))) continue;\n"
    "        float d = texture(u_depth, q).r;\n"
    "        if (d >= 1.0) continue;\n"
    "        vec4 w = u_inv_view_proj * vec4(vec3(q, d) * 2.0 - 1.0, 1.0);\n"
    "        vec3 v = w.xyz / w.w - p;\n"
    "        float len = length(v);\n"
    "        if (len < 1e-6) continue;\n"
    "        float fade = clamp(1.0 - len / (2.0 * u_ao_radius), 0.0, 1.0);\n"
    "        occluded += max(dot(v / len, n) - 0.2, 0.0) * fade;\n"
    "    }\n"
    "    return clamp(1.0 - 4.0 * occluded / 12.0, 0.0, 1.0);\n"
    "}\n"
    "#else\n"
    "float ambient_occlusion(vec3 p, vec3 n) { return 1.0; }\n"
    "#endif\n"
    "vec3 tone_map(vec3 c) {\n"
    "    c *= u_exposure;\n"
    "#ifdef WITH_TONE\n"
    "    if (u_tone == 1) { // ACES filmic (Narkowicz's fit of the RRT and ODT)\n"
    "        c *= 0.6;\n"
    "        return clamp(c * (2.51 * c + 0.03) / (c * (2.43 * c + 0.59) + 0.14), 0.0, 1.0);\n"
    "    }\n"
    "    if (u_tone == 2) { // Khronos PBR Neutral\n"
    "        float x = min(c.r, min(c.g, c.b));\n"
    "        float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;\n"
    "        c -= offset;\n"
    "        float peak = max(c.r, max(c.g, c.b));\n"
    "        if (peak < 0.76) return c;\n"
    "        float d = 0.24, np = 1.0 - d * d / (peak + d - 0.76);\n"
    "        c *= np / peak;\n"
    "        float g = 1.0 - 1.0 / (0.15 * (peak - np) + 1.0);\n"
    "        return mix(c, vec3(np), g);\n"
    "    }\n"
    "#endif\n"
    "    return c;\n"
    "}\n"
    "vec3 to_srgb(vec3 c) {\n"
    "    c = clamp(c, 0.0, 1.0);\n"
    "    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));\n"
    "}\n";

static const char *const PBR =
    "uniform float u_metallic;\n"
    "uniform float u_roughness;\n"
    "uniform vec3 u_emissive;\n"
    "uniform float u_normal_scale;\n"
    "uniform float u_occlusion_strength;\n"
    "uniform bvec4 u_maps;          // metallic-roughness, normal, occlusion, emissive present\n"
    "uniform sampler2D u_map_mr;\n"
    "uniform sampler2D u_map_normal;\n"
    "uniform sampler2D u_map_occlusion;\n"
    "uniform sampler2D u_map_emissive;\n"
    "const float PI = 3.14159265;\n"
    "vec3 direct(vec3 n, vec3 v, vec3 l, vec3 radiance, vec3 albedo, vec3 f0, float alpha) {\n"
    "    float nl = max(dot(n, l), 0.0);\n"
    "    if (nl <= 0.0) return vec3(0.0);\n"
    "    vec3 h = normalize(l + v);\n"
    "    float nv = max(dot(n, v), 1e-4), nh = max(dot(n, h), 0.0), vh = max(dot(v, h), 0.0);\n"
    "    float a2 = alpha * alpha;\n"
    "    float d = a2 / (PI * pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));\n"
    "    float vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));\n"
    "    vec3 f = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);\n"
    "    return ((1.0 - f) * albedo / PI + f * d * vis) * radiance * nl;\n"
    "}\n"
    "mat3 tangent_frame(vec3 n, vec3 p, vec2 uv) {\n"
    "    if (dot(v_tangent.xyz, v_tangent.xyz) > 1e-12) {\n"
    "        vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));\n"
    "        return mat3(t, (v_tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t), n);\n"
    "    }\n"
    "    // none in the mesh: the cotangent frame of the UVs' screen-space derivatives\n"
    "    vec3 dp1 = dFdx(p), dp2 = dFdy(p);\n"
    "    vec2 duv1 = dFdx(uv), duv2 = dFdy(uv);\n"
    "    vec3 dp2perp = cross(dp2, n), dp1perp = cross(n, dp1);\n"
    "    vec3 t = dp2perp * duv1.x + dp1perp * duv2.x, b = dp2perp * duv1.y + dp1perp * duv2.y;\n"
    "    float m = max(dot(t, t), dot(b, b));\n"
    "    return m > 0.0 ? mat3(t * inversesqrt(m), b * inversesqrt(m), n) : mat3(vec3(0.0), vec3(0.0), n);\n"
    "}\n"
    "vec3 shade_pbr(vec3 albedo_in, vec3 n) {\n"
    "    float metallic = u_metallic, rough = u_roughness;\n"
    "    if (u_maps.x) {\n"
    "        vec4 mr = texture(u_map_mr, v_uv);\n"
    "        rough *= mr.g;\n"
    "        metallic *= mr.b;\n"
    "    }\n"
    "    rough = clamp(rough, 0.03, 1.0);\n"
    "    metallic = clamp(metallic, 0.0, 1.0);\n"
    "    if (u_maps.y) {\n"
    "        vec3 t = texture(u_map_normal, v_uv).rgb * 2.0 - 1.0;\n"
    "        t.xy *= u_normal_scale;\n"
    "        vec3 mapped = tangent_frame(n, v_world, v_uv) * t;\n"
    "        if (dot(mapped, mapped) > 1e-12) n = normalize(mapped);\n"
    "    }\n"
    "    vec3 v = normalize(u_eye - v_world);\n"
    "    float nv = max(dot(n, v), 1e-4);\n"
    "    vec3 albedo = albedo_in * (1.0 - metallic);\n"
    "    vec3 f0 = mix(vec3(0.04), albedo_in, metallic);\n"
    "    float alpha = rough * rough;\n"
    "    vec3 color = u_env_direct * (direct(n, v, u_key_dir, vec3(2.6, 2.5, 2.35), albedo, f0, alpha)\n"
    "                                   * shadow_visibility(v_world, n)\n"
    "                               + direct(n, v, u_fill_dir, vec3(0.75, 0.85, 1.0), albedo, f0, alpha));\n"
    "    float ao = u_maps.z ? 1.0 + u_occlusion_strength * (texture(u_map_occlusion, v_uv).r - 1.0) : 1.0;\n"
    "    vec3 r = reflect(-v, n);\n"
    "    vec3 prefiltered = env_radiance(r, rough * float(ENV_LEVELS - 1));\n"
    "    vec2 ab = texture(u_brdf, vec2(nv, rough)).rg;\n"
    "    color += ao * (albedo * env_irradiance(n) + prefiltered * (f0 * ab.x + ab.y));\n"
    "    vec3 e = u_emissive;\n"
    "    if (u_maps.w) e *= texture(u_map_emissive, v_uv).rgb;\n"
    "    return color + e;\n"
    "}\n";

static const char *const MESH_FS =
    "uniform vec4 u_base_color;     // linear RGB\n"
    "uniform bool u_use_texture;\n"
    "uniform sampler2D u_texture;   // sRGB texture, decoded to linear by GL\n"
    "uniform int u_mode;            // 0 unlit, 1 Phong, 2 Gouraud, 3 flat, 4 physically based\n"
    "uniform bool u_flat;           // the mesh's triangles are flat (its file gave no normals): PBR too\n"
    "uniform bool u_vertex_colors;  // v_color multiplies the base colour\n"
    "uniform float u_alpha_cutoff;  // alpha mask: fragments below it are not drawn (-1: opaque)\n"
    "uniform bool u_alpha_coverage; // alpha blend: the alpha goes out, as the pixel's coverage\n"
    "uniform bool u_heat;\n"
    "uniform vec4 u_override;       // a > 0: draw this sRGB colour (wireframe)\n"
    "out vec4 o_color;\n"
    "vec3 heat_color(float w) {\n"
    "    w = clamp(w, 0.0, 1.0);\n"
    "    vec3 c0 = vec3(0.02, 0.03, 0.35), c1 = vec3(0.0, 0.55, 0.9), c2 = vec3(0.1, 0.8, 0.1);\n"
    "    vec3 c3 = vec3(0.95, 0.85, 0.05), c4 = vec3(0.9, 0.05, 0.02);\n"
    "    if (w < 0.25) return mix(c0, c1, w * 4.0);\n"
    "    if (w < 0.5) return mix(c1, c2, w * 4.0 - 1.0);\n"
    "    if (w < 0.75) return mix(c2, c3, w * 4.0 - 2.0);\n"
    "    return mix(c3, c4, w * 4.0 - 3.0);\n"
    "}\n"
    "void main() {\n"

    "    if (u_override.a > 0.0) {\n"
    "        o_color = vec4(u_override.rgb, 1.0);\n"
    "        return;\n"
    "    }\n"
    "    vec3 albedo = u_vertex_colors ? u_base_color.rgb * v_color.rgb : u_base_color.rgb;\n"
    "    float alpha = u_vertex_colors ? u_base_color.a * v_color.a : u_base_color.a;\n"
    "    if (u_use_texture) {\n"
    "        vec4 texel = texture(u_texture, v_uv);\n"
    "        albedo *= texel.rgb;\n"
    "        alpha *= texel.a;\n"
    "    }\n"
    "    if (alpha < u_alpha_cutoff)\n"
    "        discard;\n"
    "    alpha = u_alpha_coverage ? clamp(alpha, 0.0, 1.0) : 1.0;\n"
    "    if (u_heat)\n"
    "        albedo = heat_color(v_heat);\n"
    "    vec3 color = albedo;\n"
    "    float ao = 1.0;\n"
    "    if (u_mode == 2) {\n"
    "        color = albedo * v_diffuse + v_specular;\n"
    "        ao = ambient_occlusion(v_world, normalize(v_normal) * (gl_FrontFacing ? 1.0 : -1.0));\n"
    "    } else if (u_mode != 0) {\n"
    "        bool faceted = u_mode == 3 || u_flat;\n"
    "        vec3 n = faceted ? normalize(cross(dFdx(v_world), dFdy(v_world))) : normalize(v_normal);\n"
    "        if (!faceted && !gl_FrontFacing)\n"
    "            n = -n;\n"
    "        ao = ambient_occlusion(v_world, n);\n"
    "        if (u_mode == 4) {\n"
    "            o_color = vec4(to_srgb(tone_map(ao * shade_pbr(albedo, n))), alpha);\n"
    "            return;\n"
    "        }\n"
    "        vec3 diffuse, specular;\n"
    "        light_terms(n, v_world, shadow_visibility(v_world, n), diffuse, specular);\n"
    "        color = albedo * diffuse + specular;\n"
    "    }\n"
    "    o_color = vec4(to_srgb(tone_map(ao * color)), alpha);\n"
    "}\n";

/* Normals as lines: the mesh vertex stage runs unchanged, this stage turns each vertex
 * (drawn as a point) into a line along its normal. */
static const char *const NORMALS_GS =
    "layout(points) in;\n"
    "layout(line_strip, max_vertices = 2) out;\n"
    "in vec3 v_world[];\n"
    "in vec3 v_normal[];\n"
    "uniform mat4 u_view_proj;\n"
    "uniform float u_normal_length;\n"
    "out vec3 g_color;\n"
    "void main() {\n"
    "    g_color = vec3(0.2, 0.45, 1.0);\n"
    "    gl_Position = u_view_proj * vec4(v_world[0], 1.0);\n"
    "    EmitVertex();\n"
    "    g_color = vec3(0.75, 0.9, 1.0);\n"
    "    gl_Position = u_view_proj * vec4(v_world[0] + v_normal[0] * u_normal_length, 1.0);\n"
    "    EmitVertex();\n"
    "    EndPrimitive();\n"
    "}\n";

static const char *const NORMALS_FS = "in vec3 g_color;\n"
                                      "out vec4 o_color;\n"
                                      "void main() { o_color = vec4(g_color, 1.0); }\n";

/* Overlay: positions (world or pixel space, through u_matrix) and sRGB byte colours. */
static const char *const OVERLAY_VS = "layout(location = 0) in vec3 a_position;\n"
                                      "layout(location = 1) in vec4 a_color;\n"
                                      "uniform mat4 u_matrix;\n"
                                      "uniform float u_point_size;\n"
                                      "out vec4 v_color;\n"
                                      "void main() {\n"
                                      "    v_color = a_color;\n"
                                      "    gl_PointSize = u_point_size;\n"
                                      "    gl_Position = u_matrix * vec4(a_position, 1.0);\n"
                                      "}\n";

static const char *const OVERLAY_FS = "in vec4 v_color;\n"
                                      "uniform bool u_round;\n"
                                      "out vec4 o_color;\n"
                                      "void main() {\n"
                                      "    if (u_round && length(gl_PointCoord - vec2(0.5)) > 0.5)\n"
                                      "        discard;\n"
                                      "    o_color = v_color;\n"
                                      "}\n";

/* True when the shader compiled or the program linked; otherwise the error gets GL's log. */
static bool gl_succeeded(GLuint object, bool program, const char *what, sinew_error *error)
{
    GLint ok = 0;
    char log[400] = "";
    if (program)
        glGetProgramiv(object, GL_LINK_STATUS, &ok);
    else
        glGetShaderiv(object, GL_COMPILE_STATUS, &ok);
    if (ok)
        return true;
    if (program)
        glGetProgramInfoLog(object, sizeof log, NULL, log);
    else
        glGetShaderInfoLog(object, sizeof log, NULL, log);
    sinew_fail(error, SINEW_ERROR_GRAPHICS, "the %s %s: %s", what,
               program ? "program does not link" : "shader does not compile", log);
    return false;
}

static GLuint compile(GLenum stage, const char *const *parts, int part_count, const char *what, sinew_error *error)
{
    GLuint shader = glCreateShader(stage);
    glShaderSource(shader, part_count, parts, NULL);
    glCompileShader(shader);
    if (!gl_succeeded(shader, false, what, error)) {
        glDeleteShader(shader);
        return 0;
    }
    return shader;
}

/* A triangle covering the screen, from gl_VertexID alone (no buffers); v_ndc: its clip-space xy. */
static const char *const FULLSCREEN_VS =
    "out vec2 v_ndc;\n"
    "void main() {\n"
    "    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);\n"
    "    v_ndc = p;\n"
    "    gl_Position = vec4(p, 1.0, 1.0);\n"
    "}\n";

/* The environment behind everything: the direction through each pixel, at a blurred level. */
static const char *const BACKGROUND_FS = "in vec2 v_ndc;\n"
                                         "uniform float u_lod;\n"
                                         "out vec4 o_color;\n"
                                         "void main() {\n"
                                         "    vec4 a = u_inv_view_proj * vec4(v_ndc, -1.0, 1.0);\n"
                                         "    vec4 b = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);\n"
                                         "    vec3 d = b.xyz / b.w - a.xyz / a.w;\n"
                                         "    o_color = vec4(to_srgb(tone_map(env_radiance(d, u_lod))), 1.0);\n"
                                         "}\n";

/* The shadow catcher: a square on the ground, black with the shadow's and the occlusion's
 * darkness as coverage, fading out towards its edges. */
static const char *const GROUND_VS = "layout(location = 0) in vec3 a_position;\n"
                                     "uniform mat4 u_view_proj;\n"
                                     "out vec3 v_world;\n"
                                     "void main() {\n"
                                     "    v_world = a_position;\n"
                                     "    gl_Position = u_view_proj * vec4(a_position, 1.0);\n"
                                     "}\n";
static const char *const GROUND_FS =
    "in vec3 v_world;\n"
    "uniform bool u_ao;\n"
    "uniform vec3 u_center;\n"
    "uniform float u_extent;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 up = vec3(0.0, 1.0, 0.0);\n"
    "    float r = length(v_world.xz - u_center.xz) / u_extent;\n"
    "    if (r >= 1.0) discard;\n"
    "    float lit = shadow_visibility(v_world, up);\n"
    "    if (u_ao && r < 0.4) lit *= ambient_occlusion(v_world, up); // contact: under the model only\n"
    "    float a = (1.0 - lit) * 0.6 * (1.0 - r);\n"
    "    if (a < 0.002) discard; // nothing to blend\n"
    "    o_color = vec4(0.0, 0.0, 0.0, a);\n"
    "}\n";

/* Outlines: where the depth pre-pass jumps (silhouettes against the background or against
 * what lies behind, and creases), a dark line over the frame. Linear depths come from the
 * projection's near and far planes. */
static const char *const OUTLINE_FS =
    "in vec2 v_ndc;\n"
    "uniform sampler2D u_depth;\n"
    "uniform vec2 u_viewport;\n"
    "uniform vec2 u_planes;     // near, far\n"
    "uniform bool u_ortho;\n"
    "uniform vec4 u_color;\n"
    "out vec4 o_color;\n"
    "float linear_depth(float d) {\n"
    "    float n = u_planes.x, f = u_planes.y;\n"
    "    return u_ortho ? n + d * (f - n) : n * f / (f - d * (f - n));\n"
    "}\n"
    "float depth_at(vec2 px) { return texture(u_depth, px / u_viewport).r; }\n"
    "void main() {\n"
    "    vec2 px = gl_FragCoord.xy;\n"
    "    float d0 = depth_at(px);\n"
    "    float z0 = linear_depth(d0);\n"
    "    float edge = 0.0;\n"
    "    float zs[8];\n"
    "    const vec2 offs[8] = vec2[8](vec2(1, 0), vec2(-1, 0), vec2(0, 1), vec2(0, -1),\n"
    "                                 vec2(1, 1), vec2(-1, -1), vec2(1, -1), vec2(-1, 1));\n"
    "    for (int i = 0; i < 8; i++) {\n"
    "        float d = depth_at(px + offs[i]);\n"
    "        if ((d >= 1.0) != (d0 >= 1.0)) { edge = 1.0; continue; }\n"
    "        zs[i] = linear_depth(d);\n"
    "    }\n"
    "    if (edge == 0.0 && d0 < 1.0) {\n"
    "        // a second difference across the pixel, relative to its depth: creases and steps, not slopes\n"
    "        for (int i = 0; i < 8; i += 2) {\n"
    "            float dd = abs(zs[i] + zs[i + 1] - 2.0 * z0) / z0;\n"
    "            edge = max(edge, smoothstep(0.01, 0.03, dd));\n"
    "        }\n"
    "    }\n"
    "    if (edge <= 0.0) discard;\n"
    "    o_color = vec4(u_color.rgb, u_color.a * edge);\n"
    "}\n";

/* FXAA (Lottes's, its compact form): along the edge the luma of the four diagonal neighbours
 * shows, two and then four taps; the wider blend unless it leaves the neighbourhood's luma range.
 * Alpha is the pixel's own. */
static const char *const FXAA_FS =
    "in vec2 v_ndc;\n"
    "uniform sampler2D u_color;\n"
    "uniform vec2 u_texel;\n"
    "out vec4 o_color;\n"
    "float luma(vec3 c) { return dot(c, vec3(0.299, 0.587, 0.114)); }\n"
    "vec3 at(vec2 uv) { return texture(u_color, uv).rgb; }\n"
    "void main() {\n"
    "    vec2 uv = gl_FragCoord.xy * u_texel;\n"
    "    vec4 m = texture(u_color, uv);\n"
    "    float nw = luma(at(uv + vec2(-1.0, -1.0) * u_texel)), ne = luma(at(uv + vec2(1.0, -1.0) * u_texel));\n"
    "    float sw = luma(at(uv + vec2(-1.0, 1.0) * u_texel)), se = luma(at(uv + vec2(1.0, 1.0) * u_texel));\n"
    "    float lm = luma(m.rgb);\n"
    "    float lo = min(lm, min(min(nw, ne), min(sw, se))), hi = max(lm, max(max(nw, ne), max(sw, se)));\n"
    "    if (hi - lo < max(0.0312, hi * 0.125)) { o_color = m; return; }\n"
    "    vec2 dir = vec2(-((nw + ne) - (sw + se)), (nw + sw) - (ne + se));\n"
    "    float reduce = max((nw + ne + sw + se) * 0.03125, 1.0 / 128.0);\n"
    "    dir = clamp(dir / (min(abs(dir.x), abs(dir.y)) + reduce), -8.0, 8.0) * u_texel;\n"
    "    vec3 a = 0.5 * (at(uv + dir * (1.0 / 3.0 - 0.5)) + at(uv + dir * (2.0 / 3.0 - 0.5)));\n"
    "    vec3 b = a * 0.5 + 0.25 * (at(uv - dir * 0.5) + at(uv + dir * 0.5));\n"
    "    float lb = luma(b);\n"
    "    o_color = vec4(lb < lo || lb > hi ? a : b, m.a);\n"
    "}\n";

/* Links a program from a vertex, an optional geometry and a fragment stage, each given as
 * parts after the version line. */
static GLuint link_parts(const char *const *vs, int vs_count, const char *gs, const char *const *fs, int fs_count,
                         const char *what, sinew_error *error)
{
    static const char *const VERSION = "#version 330 core\n";
    const char *vs_parts[8] = {VERSION}, *gs_parts[2] = {VERSION, gs}, *fs_parts[8] = {VERSION};
    for (int i = 0; i < vs_count; i++)
        vs_parts[1 + i] = vs[i];
    for (int i = 0; i < fs_count; i++)
        fs_parts[1 + i] = fs[i];
    GLuint stages[3] = {0}, program = 0;
    stages[0] = compile(GL_VERTEX_SHADER, vs_parts, 1 + vs_count, what, error);
    stages[1] = gs ? compile(GL_GEOMETRY_SHADER, gs_parts, 2, what, error) : 0;
    stages[2] = compile(GL_FRAGMENT_SHADER, fs_parts, 1 + fs_count, what, error);
    if (!stages[0] || (gs && !stages[1]) || !stages[2])
        goto out_delete_stages;
    program = glCreateProgram();
    for (int i = 0; i < 3; i++)
        if (stages[i])
            glAttachShader(program, stages[i]);
    glLinkProgram(program);
    if (!gl_succeeded(program, true, what, error)) {
        glDeleteProgram(program);
        program = 0;
    }
out_delete_stages:
    for (int i = 0; i < 3; i++)
        if (stages[i])
            glDeleteShader(stages[i]);
    return program;
}

sinew_result render_programs_create(render_programs *programs, sinew_error *error)
{
    const char *mesh_vs[] = {LIGHTING, MESH_VS_HEAD, MESH_VS};
    const char *normals_fs[] = {NORMALS_FS};
    const char *overlay_vs[] = {OVERLAY_VS}, *overlay_fs[] = {OVERLAY_FS};
    const char *fullscreen_vs[] = {FULLSCREEN_VS};
    const char *background_fs[] = {"#define WITH_TONE\n", EFFECTS, EFFECTS_POST, BACKGROUND_FS};
    const char *ground_vs[] = {GROUND_VS},
               *ground_fs[] = {"#define WITH_SHADOWS\n#define WITH_AO\n", EFFECTS, EFFECTS_POST, GROUND_FS};
    const char *outline_fs[] = {OUTLINE_FS}, *fxaa_fs[] = {FXAA_FS};
    /* depth alone (shadow map, pre-pass): the mesh vertex stage, a fragment stage that does nothing */
    const char *depth_fs[] = {MESH_FS_INPUTS, "void main() {}\n"};
    if (!(programs->mesh = render_mesh_variant(programs, 0, error)) ||
        !(programs->normals = link_parts(mesh_vs, 3, NORMALS_GS, normals_fs, 1, "normals", error)) ||
        !(programs->overlay = link_parts(overlay_vs, 1, NULL, overlay_fs, 1, "overlay", error)) ||
        !(programs->background = link_parts(fullscreen_vs, 1, NULL, background_fs, 4, "background", error)) ||
        !(programs->ground = link_parts(ground_vs, 1, NULL, ground_fs, 4, "ground", error)) ||
        !(programs->outline = link_parts(fullscreen_vs, 1, NULL, outline_fs, 1, "outline", error)) ||
        !(programs->fxaa = link_parts(fullscreen_vs, 1, NULL, fxaa_fs, 1, "fxaa", error)) ||
        !(programs->depth = link_parts(mesh_vs, 3, NULL, depth_fs, 2, "depth", error))) {
        render_programs_free(programs);
        return error ? error->kind : SINEW_ERROR_GRAPHICS;
    }
    return SINEW_OK;
}

/* The mesh program with only the effects `flags` asks for compiled in (llvmpipe pays for
 * every instruction of a fragment stage, taken or not). */
GLuint render_mesh_variant(render_programs *programs, unsigned flags, sinew_error *error)
{
    flags &= RENDER_MESH_VARIANTS - 1;
    if (programs->mesh_variant[flags])
        return programs->mesh_variant[flags];
    char defines[96];
    snprintf(defines, sizeof defines, "%s%s%s", flags & RENDER_WITH_SHADOWS ? "#define WITH_SHADOWS\n" : "",
             flags & RENDER_WITH_AO ? "#define WITH_AO\n" : "", flags & RENDER_WITH_TONE ? "#define WITH_TONE\n" : "");
    const char *mesh_vs[] = {LIGHTING, MESH_VS_HEAD, MESH_VS};
    const char *mesh_fs[] = {defines, LIGHTING, MESH_FS_INPUTS, EFFECTS, EFFECTS_POST, PBR, MESH_FS};
    programs->mesh_variant[flags] = link_parts(mesh_vs, 3, NULL, mesh_fs, 7, "mesh", error);
    return programs->mesh_variant[flags];
}

void render_programs_free(render_programs *programs)
{
    for (int i = 0; i < RENDER_MESH_VARIANTS; i++)
        glDeleteProgram(programs->mesh_variant[i]);
    glDeleteProgram(programs->normals);
    glDeleteProgram(programs->overlay);
    glDeleteProgram(programs->background);
    glDeleteProgram(programs->ground);
    glDeleteProgram(programs->outline);
    glDeleteProgram(programs->fxaa);
    glDeleteProgram(programs->depth);
    memset(programs, 0, sizeof *programs);
}
