/* GLSL 3.30 sources of the renderer and the helpers that compile and link them.
 *
 * Index: mesh vertex stage (skinning, normals and tangents through the cofactor, heat
 * weight, Gouraud lighting) - physically based shading - mesh fragment stage (materials,
 * heat map, flat/Gouraud/Phong/PBR, sRGB out) -
 * normals geometry stage (a line per vertex) - overlay stages (coloured lines, points,
 * triangles, text) - compile/link.
 */
#include <stdio.h>

#include "internal.h"

/* Lighting shared by the vertex (Gouraud) and fragment (flat, Phong) stages: a key and a
 * fill light fixed to the camera, a sky/ground ambient, and a mild Blinn-Phong highlight.
 * Works in linear RGB. */
static const char *const LIGHTING =
    "uniform vec3 u_key_dir;   // towards the key light, world space\n"
    "uniform vec3 u_fill_dir;  // towards the fill light\n"
    "uniform vec3 u_eye;\n"
    "void light_terms(vec3 n, vec3 p, out vec3 diffuse, out vec3 specular) {\n"
    "    vec3 v = normalize(u_eye - p);\n"
    "    float hemi = 0.5 + 0.5 * n.y;\n"
    "    vec3 ambient = mix(vec3(0.10, 0.09, 0.08), vec3(0.20, 0.22, 0.26), hemi);\n"
    "    float key = max(dot(n, u_key_dir), 0.0);\n"
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
    "    v_heat = u_heat_joint < 0 ? u_heat_rigid : heat_of(a_joints0, a_weights0) + heat_of(a_joints1, a_weights1);\n"
    "    v_diffuse = vec3(1.0);\n"
    "    v_specular = vec3(0.0);\n"
    "    if (u_gouraud)\n"
    "        light_terms(v_normal, v_world, v_diffuse, v_specular);\n"
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
 * Smith-GGX visibility and Schlick Fresnel): the key and fill lights plus an environment of
 * a sky over a ground, its diffuse part the hemisphere's irradiance and its specular part
 * the split-sum approximation (the sky sampled along the reflection, blurred towards the
 * irradiance with roughness; Karis's analytic environment BRDF), then Khronos PBR Neutral
 * tone mapping. */
/* The mesh fragment stage's inputs, before PBR and MESH_FS, which read them. */
static const char *const MESH_FS_INPUTS = "in vec3 v_world;\n"
                                          "in vec3 v_normal;\n"
                                          "in vec4 v_tangent;\n"
                                          "in vec2 v_uv;\n"
                                          "in float v_heat;\n"
                                          "in vec3 v_diffuse;\n"
                                          "in vec3 v_specular;\n";

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
    "vec3 sky(vec3 d) {\n"
    "    vec3 horizon = vec3(0.75, 0.75, 0.76), zenith = vec3(0.46, 0.5, 0.58), ground = vec3(0.2, 0.19, 0.18);\n"
    "    return d.y >= 0.0 ? mix(horizon, zenith, sqrt(d.y)) : mix(horizon * 0.6, ground, sqrt(-d.y));\n"
    "}\n"
    "vec3 irradiance(vec3 n) {  // cosine-weighted sky over ground, divided by pi\n"
    "    return mix(vec3(0.24, 0.23, 0.22), vec3(0.56, 0.58, 0.63), 0.5 + 0.5 * n.y);\n"
    "}\n"
    "vec2 env_brdf(float nv, float rough) {\n"
    "    vec4 r = rough * vec4(-1.0, -0.0275, -0.572, 0.022) + vec4(1.0, 0.0425, 1.04, -0.04);\n"
    "    float a = min(r.x * r.x, exp2(-9.28 * nv)) * r.x + r.y;\n"
    "    return vec2(-1.04, 1.04) * a + r.zw;\n"
    "}\n"
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
    "vec3 tone_map(vec3 c) {  // Khronos PBR Neutral\n"
    "    float x = min(c.r, min(c.g, c.b));\n"
    "    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;\n"
    "    c -= offset;\n"
    "    float peak = max(c.r, max(c.g, c.b));\n"
    "    if (peak < 0.76) return c;\n"
    "    float d = 0.24, np = 1.0 - d * d / (peak + d - 0.76);\n"
    "    c *= np / peak;\n"
    "    float g = 1.0 - 1.0 / (0.15 * (peak - np) + 1.0);\n"
    "    return mix(c, vec3(np), g);\n"
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
    "    vec3 color = direct(n, v, u_key_dir, vec3(2.6, 2.5, 2.35), albedo, f0, alpha)\n"
    "               + direct(n, v, u_fill_dir, vec3(0.75, 0.85, 1.0), albedo, f0, alpha);\n"
    "    float ao = u_maps.z ? 1.0 + u_occlusion_strength * (texture(u_map_occlusion, v_uv).r - 1.0) : 1.0;\n"
    "    vec3 r = reflect(-v, n);\n"
    "    vec3 prefiltered = mix(sky(r), irradiance(r), rough * rough);\n"
    "    vec2 ab = env_brdf(nv, rough);\n"
    "    color += ao * (albedo * irradiance(n) + prefiltered * (f0 * ab.x + ab.y));\n"
    "    vec3 e = u_emissive;\n"
    "    if (u_maps.w) e *= texture(u_map_emissive, v_uv).rgb;\n"
    "    return tone_map(color + e);\n"
    "}\n";

static const char *const MESH_FS =
    "uniform vec4 u_base_color;     // linear RGB\n"
    "uniform bool u_use_texture;\n"
    "uniform sampler2D u_texture;   // sRGB texture, decoded to linear by GL\n"
    "uniform int u_mode;            // 0 unlit, 1 Phong, 2 Gouraud, 3 flat, 4 physically based\n"
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
    "vec3 to_srgb(vec3 c) {\n"
    "    c = clamp(c, 0.0, 1.0);\n"
    "    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));\n"
    "}\n"
    "void main() {\n"
    "    if (u_override.a > 0.0) {\n"
    "        o_color = vec4(u_override.rgb, 1.0);\n"
    "        return;\n"
    "    }\n"
    "    vec3 albedo = u_base_color.rgb;\n"
    "    if (u_use_texture)\n"
    "        albedo *= texture(u_texture, v_uv).rgb;\n"
    "    if (u_heat)\n"
    "        albedo = heat_color(v_heat);\n"
    "    vec3 color = albedo;\n"
    "    if (u_mode == 2) {\n"
    "        color = albedo * v_diffuse + v_specular;\n"
    "    } else if (u_mode != 0) {\n"
    "        vec3 n = u_mode == 3 ? normalize(cross(dFdx(v_world), dFdy(v_world))) : normalize(v_normal);\n"
    "        if (u_mode != 3 && !gl_FrontFacing)\n"
    "            n = -n;\n"
    "        if (u_mode == 4) {\n"
    "            o_color = vec4(to_srgb(shade_pbr(albedo, n)), 1.0);\n"
    "            return;\n"
    "        }\n"
    "        vec3 diffuse, specular;\n"
    "        light_terms(n, v_world, diffuse, specular);\n"
    "        color = albedo * diffuse + specular;\n"
    "    }\n"
    "    o_color = vec4(to_srgb(color), 1.0);\n"
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

/* Links a program from a vertex, an optional geometry and a fragment stage, each made of
 * the version line, `lighting` when asked, and the stage's body (the vertex stage's in two
 * parts; the fragment stage's head, when given, followed by the PBR functions). */
static GLuint link_program(const char *vs_head, const char *vs, const char *gs, const char *fs_head, const char *fs,
                           bool lighting, const char *what, sinew_error *error)
{
    static const char *const VERSION = "#version 330 core\n";
    const char *vs_parts[] = {VERSION, lighting ? LIGHTING : "", vs_head ? vs_head : "", vs};
    const char *gs_parts[] = {VERSION, gs ? gs : ""};
    const char *fs_parts[] = {VERSION, lighting ? LIGHTING : "", fs_head ? fs_head : "", fs_head ? PBR : "", fs};
    GLuint stages[3] = {0}, program = 0;
    stages[0] = compile(GL_VERTEX_SHADER, vs_parts, 4, what, error);
    stages[1] = gs ? compile(GL_GEOMETRY_SHADER, gs_parts, 2, what, error) : 0;
    stages[2] = compile(GL_FRAGMENT_SHADER, fs_parts, 5, what, error);
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
    programs->mesh = link_program(MESH_VS_HEAD, MESH_VS, NULL, MESH_FS_INPUTS, MESH_FS, true, "mesh", error);
    if (!programs->mesh)
        goto fail;
    programs->normals = link_program(MESH_VS_HEAD, MESH_VS, NORMALS_GS, NULL, NORMALS_FS, true, "normals", error);
    if (!programs->normals)
        goto fail;
    programs->overlay = link_program(NULL, OVERLAY_VS, NULL, NULL, OVERLAY_FS, false, "overlay", error);
    if (!programs->overlay)
        goto fail;
    return SINEW_OK;
fail:
    render_programs_destroy(programs);
    return error ? error->kind : SINEW_ERROR_GRAPHICS;
}

void render_programs_destroy(render_programs *programs)
{
    glDeleteProgram(programs->mesh);
    glDeleteProgram(programs->normals);
    glDeleteProgram(programs->overlay);
    programs->mesh = programs->normals = programs->overlay = 0;
}
