/* Frame effects: image-based lighting on the GPU, the key light's shadow map, the depth
 * pre-pass (ambient occlusion, outlines), and the passes that draw no model (the environment
 * as background, the ground that catches shadows and occlusion, the outline).
 *
 * Index: environment upload - per-frame plan (lights, matrices, targets) - passes' targets -
 * uniforms - background, ground and outline passes.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "internal.h"

#define BRDF_SIZE 32
/* The environment's level shown behind the scene (blurred, as f3d and Blender's viewport blur it). */
#define BACKGROUND_LOD 1.5f

void render_effects_free(render_effects *fx)
{
    glDeleteTextures(1, &fx->env_texture);
    glDeleteTextures(1, &fx->brdf_texture);
    glDeleteTextures(1, &fx->shadow_texture);
    glDeleteTextures(1, &fx->depth_texture);
    glDeleteFramebuffers(1, &fx->shadow_fbo);
    glDeleteFramebuffers(1, &fx->depth_fbo);
    glDeleteVertexArrays(1, &fx->empty_vao);
    glDeleteVertexArrays(1, &fx->ground_vao);
    glDeleteBuffers(1, &fx->ground_buffer);
    glDeleteFramebuffers(1, &fx->aa_fbo);
    glDeleteTextures(1, &fx->aa_color);
    glDeleteRenderbuffers(1, &fx->aa_depth);
    memset(fx, 0, sizeof *fx);
}

/* A 2D texture of `data` (NULL: uninitialised), filtered as asked, clamped to its edges; left unbound. */
static GLuint make_texture(GLint internal, int width, int height, GLenum format, GLenum type, const void *data,
                           GLint filter)
{
    GLuint texture;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, width, height, 0, format, type, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return texture;
}

/* Puts a prefiltered environment on the GPU (and the BRDF table the first time). */
static void upload_env(render_effects *fx, const render_env *env, bool custom)
{
    if (!fx->env_texture)
        glGenTextures(1, &fx->env_texture);
    glBindTexture(GL_TEXTURE_2D, fx->env_texture);
    for (int i = 0; i < RENDER_ENV_LEVELS; i++)
        glTexImage2D(GL_TEXTURE_2D, i, GL_RGB16F, RENDER_ENV_WIDTH >> i, (RENDER_ENV_WIDTH / 2) >> i, 0, GL_RGB,
                     GL_FLOAT, env->level[i]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, RENDER_ENV_LEVELS - 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    memcpy(fx->sh, env->sh, sizeof fx->sh);
    memcpy(fx->light_dir, env->light_dir, sizeof fx->light_dir);
    fx->directionality = env->directionality;
    fx->env_custom = custom;
    fx->env_ready = true;
    if (!fx->brdf_texture) {
        float table[BRDF_SIZE * BRDF_SIZE * 2];
        render_brdf_table(BRDF_SIZE, table);
        fx->brdf_texture = make_texture(GL_RG16F, BRDF_SIZE, BRDF_SIZE, GL_RG, GL_FLOAT, table, GL_LINEAR);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
}

sinew_result render_effects_set_environment(render_effects *fx, const char *path, sinew_error *error)
{
    render_env env;
    if (path) {
        sinew_result result = render_env_load(path, &env, error);
        if (result != SINEW_OK)
            return result;
    } else if (!render_env_studio(&env)) {
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "out of memory making the studio environment");
    }
    upload_env(fx, &env, path != NULL);
    render_env_free(&env);
    return SINEW_OK;
}

/* A depth texture for a target: 24-bit, nearest or compared (shadows, bilinear PCF). */
static GLuint depth_texture(int width, int height, bool compare)
{
    GLuint texture = make_texture(GL_DEPTH_COMPONENT24, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, NULL,
                                  compare ? GL_LINEAR : GL_NEAREST);
    if (compare) {
        glBindTexture(GL_TEXTURE_2D, texture);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    return texture;
}

/* A framebuffer with only a depth attachment. */
static bool depth_target(GLuint *fbo, GLuint texture)
{
    GLint previous = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
    if (!*fbo)
        glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, texture, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    bool ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)previous);
    return ok;
}

/* The projection's near and far planes (perspective or parallel, OpenGL clip space). */
static void planes_of(const float *p, bool ortho, float *near_plane, float *far_plane)
{
    if (ortho) {
        *near_plane = (p[14] + 1.0f) / p[10];
        *far_plane = (p[14] - 1.0f) / p[10];
    } else {
        *near_plane = p[14] / (p[10] - 1.0f);
        *far_plane = p[14] / (p[10] + 1.0f);
    }
}

/* The light's view: an orthographic box around the scene's sphere, looking along -towards. */
static void light_matrices(render_effect_frame *ef, const float towards[3])
{
    float eye[3], up[3] = {0.0f, 1.0f, 0.0f};
    if (fabsf(towards[1]) > 0.99f)
        up[1] = 0.0f, up[2] = 1.0f;
    for (int i = 0; i < 3; i++)
        eye[i] = ef->center[i] + towards[i] * ef->radius * 2.0f;
    mat4 view, proj, vp;
    glm_lookat(eye, ef->center, up, view);
    glm_ortho(-ef->radius, ef->radius, -ef->radius, ef->radius, 0.0f, ef->radius * 4.0f, proj);
    glm_mat4_mul(proj, view, vp);
    memcpy(ef->light_view_proj, vp, sizeof ef->light_view_proj);
    /* to [0,1] for the texture lookup */
    mat4 bias = {{0.5f, 0, 0, 0}, {0, 0.5f, 0, 0}, {0, 0, 0.5f, 0}, {0.5f, 0.5f, 0.5f, 1.0f}}, shadow;
    glm_mat4_mul(bias, vp, shadow);
    memcpy(ef->shadow_matrix, shadow, sizeof ef->shadow_matrix);
    /* a texel's width along the normal keeps surfaces from shadowing themselves */
    ef->shadow_bias = 2.0f * ef->radius / (float)RENDER_SHADOW_SIZE * 1.5f;
}

sinew_result render_effects_prepare(render_effects *fx, render_effect_frame *ef, const sinew_frame *frame,
                                    const float key[3], const float view[16], const float proj[16], bool crowd,
                                    sinew_error *error)
{
    const sinew_render_options *o = frame->options;
    bool pbr = !o->unlit && o->shading == SINEW_SHADING_PBR;
    memset(ef, 0, sizeof *ef);
    ef->width = frame->width, ef->height = frame->height;
    glm_mat4_mul((vec4 *)proj, (vec4 *)view, (vec4 *)ef->view_proj);
    glm_mat4_inv((vec4 *)ef->view_proj, (vec4 *)ef->inv_view_proj);
    ef->orthographic = proj[15] == 1.0f;
    planes_of(proj, ef->orthographic, &ef->near_plane, &ef->far_plane);
    ef->exposure = exp2f(o->exposure);
    ef->tone = o->tone_mapping == SINEW_TONE_MAPPING_ACES      ? 1
               : o->tone_mapping == SINEW_TONE_MAPPING_NEUTRAL ? 2
               : o->tone_mapping == SINEW_TONE_MAPPING_AUTO    ? (pbr ? 2 : 0)
                                                               : 0;
    if ((pbr || o->environment_background) && !fx->env_ready) {
        sinew_result result = render_effects_set_environment(fx, NULL, error);
        if (result != SINEW_OK)
            return result;
    }
    ef->env_direct = fx->env_custom ? 0.0f : 1.0f;
    ef->background = o->environment_background && !o->transparent;

    /* the scene: around what the camera looks at, as large as what it framed */
    const sinew_camera *camera = frame->camera;
    float eye[3], f[3], right[3], up[3];
    sinew_camera_eye(camera, eye);
    sinew_camera_basis(camera, f, right, up);
    for (int i = 0; i < 3; i++)
        ef->center[i] = eye[i] + f[i] * camera->distance;
    ef->radius = (camera->scene_radius > 0.0f ? camera->scene_radius : camera->distance * 0.5f) * 1.1f;
    if (!(ef->radius > 1e-6f))
        ef->radius = 1.0f;
    ef->ground_height = o->grid_height;

    bool models = !o->hide_meshes && !crowd;
    ef->shadows = o->shadows && models;
    ef->ao = o->ssao && models;
    ef->outline = o->outline && models;
    ef->depth_pass = ef->ao || ef->outline;
    ef->ground = ef->shadows || ef->ao;
    if (ef->shadows) {
        float towards[3] = {key[0], key[1], key[2]};
        ef->shadow_strength = 1.0f;
        if (pbr && fx->env_custom) { /* the environment's own light, kept above the horizon */
            memcpy(towards, fx->light_dir, sizeof towards);
            if (towards[1] < 0.25f)
                towards[1] = 0.25f;
            glm_vec3_normalize(towards);
            ef->shadow_strength = 0.3f + 0.6f * fx->directionality;
        }
        light_matrices(ef, towards);
        if (!fx->shadow_texture) {
            fx->shadow_texture = depth_texture(RENDER_SHADOW_SIZE, RENDER_SHADOW_SIZE, true);
            if (!depth_target(&fx->shadow_fbo, fx->shadow_texture))
                return sinew_fail(error, SINEW_ERROR_GRAPHICS, "the shadow map's framebuffer is incomplete");
        }
    }
    if (ef->depth_pass && (fx->depth_width != frame->width || fx->depth_height != frame->height)) {
        glDeleteTextures(1, &fx->depth_texture);
        fx->depth_texture = depth_texture(frame->width, frame->height, false);
        fx->depth_width = frame->width, fx->depth_height = frame->height;
        if (!depth_target(&fx->depth_fbo, fx->depth_texture))
            return sinew_fail(error, SINEW_ERROR_GRAPHICS, "the depth pre-pass's framebuffer (%dx%d) is incomplete",
                              frame->width, frame->height);
    }
    if (!fx->empty_vao) {
        glGenVertexArrays(1, &fx->empty_vao);
        glGenVertexArrays(1, &fx->ground_vao);
        glGenBuffers(1, &fx->ground_buffer);
        glBindVertexArray(fx->ground_vao);
        glBindBuffer(GL_ARRAY_BUFFER, fx->ground_buffer);
        glBufferData(GL_ARRAY_BUFFER, 4 * 3 * sizeof(float), NULL, GL_STREAM_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, NULL);
        glBindVertexArray(0);
    }
    return SINEW_OK;
}

void render_effects_begin_shadow(render_effects *fx)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fx->shadow_fbo);
    glViewport(0, 0, RENDER_SHADOW_SIZE, RENDER_SHADOW_SIZE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
}

void render_effects_begin_depth(render_effects *fx, const render_effect_frame *ef)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fx->depth_fbo);
    glViewport(0, 0, ef->width, ef->height);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
}

void render_effects_bind(const render_effects *fx)
{
    const GLuint textures[4] = {fx->env_texture, fx->brdf_texture, fx->shadow_texture, fx->depth_texture};
    for (int i = 0; i < 4; i++) {
        glActiveTexture(GL_TEXTURE7 + i);
        glBindTexture(GL_TEXTURE_2D, textures[i]);
    }
    glActiveTexture(GL_TEXTURE0);
}

void render_effects_uniforms(const render_effects *fx, GLuint program, const render_effect_frame *ef)
{
    glUniform1i(glGetUniformLocation(program, "u_env"), 7);
    glUniform1i(glGetUniformLocation(program, "u_brdf"), 8);
    glUniform1i(glGetUniformLocation(program, "u_shadow_map"), 9);
    glUniform1i(glGetUniformLocation(program, "u_depth"), 10);
    glUniform3fv(glGetUniformLocation(program, "u_sh"), 9, &fx->sh[0][0]);
    glUniform1f(glGetUniformLocation(program, "u_env_direct"), ef->env_direct);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_shadow_matrix"), 1, GL_FALSE, ef->shadow_matrix);
    glUniform1f(glGetUniformLocation(program, "u_shadow_strength"), ef->shadows ? ef->shadow_strength : 0.0f);
    glUniform1f(glGetUniformLocation(program, "u_shadow_bias"), ef->shadow_bias);
    glUniform1i(glGetUniformLocation(program, "u_ao"), ef->ao);
    glUniform1f(glGetUniformLocation(program, "u_ao_radius"), ef->radius * 0.12f);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_inv_view_proj"), 1, GL_FALSE, ef->inv_view_proj);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_ao_view_proj"), 1, GL_FALSE, ef->view_proj);
    glUniform2f(glGetUniformLocation(program, "u_viewport"), (float)ef->width, (float)ef->height);
    glUniform1f(glGetUniformLocation(program, "u_exposure"), ef->exposure);
    glUniform1i(glGetUniformLocation(program, "u_tone"), ef->tone);
}

void render_effects_background(const render_effects *fx, const render_programs *programs, const render_effect_frame *ef)
{
    glUseProgram(programs->background);
    render_effects_uniforms(fx, programs->background, ef);
    glUniform1f(glGetUniformLocation(programs->background, "u_lod"), BACKGROUND_LOD);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(fx->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_DEPTH_TEST);
}

void render_effects_ground(const render_effects *fx, const render_programs *programs, const render_effect_frame *ef)
{
    float extent = ef->radius * 3.0f, y = ef->ground_height, cx = ef->center[0], cz = ef->center[2];
    /* only where something can darken it (every pixel of it costs): the occlusion's square under the
     * model, and where the shadow map's box meets the ground, within the fading square */
    float lo[2] = {cx, cz}, hi[2] = {cx, cz};
    if (ef->ao) {
        float reach = extent * 0.4f;
        lo[0] = cx - reach, lo[1] = cz - reach, hi[0] = cx + reach, hi[1] = cz + reach;
    }
    if (ef->shadows) {
        mat4 inverse;
        glm_mat4_inv((vec4 *)ef->light_view_proj, inverse);
        for (int k = 0; k < 4; k++) {
            vec4 a = {k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f, -1.0f, 1.0f}, b = {a[0], a[1], 1.0f, 1.0f}, wa, wb;
            glm_mat4_mulv(inverse, a, wa);
            glm_mat4_mulv(inverse, b, wb);
            float dy = wb[1] / wb[3] - wa[1] / wa[3];
            float t = fabsf(dy) > 1e-6f ? (y - wa[1] / wa[3]) / dy : 0.0f;
            float px = wa[0] / wa[3] + t * (wb[0] / wb[3] - wa[0] / wa[3]);
            float pz = wa[2] / wa[3] + t * (wb[2] / wb[3] - wa[2] / wa[3]);
            if (fabsf(dy) <= 1e-6f) /* a light along the ground: the whole square */
                px = k & 1 ? cx + extent : cx - extent, pz = k & 2 ? cz + extent : cz - extent;
            lo[0] = fminf(lo[0], px), lo[1] = fminf(lo[1], pz), hi[0] = fmaxf(hi[0], px), hi[1] = fmaxf(hi[1], pz);
        }
    }
    lo[0] = fmaxf(lo[0], cx - extent), lo[1] = fmaxf(lo[1], cz - extent);
    hi[0] = fminf(hi[0], cx + extent), hi[1] = fminf(hi[1], cz + extent);
    if (!(hi[0] > lo[0] && hi[1] > lo[1]))
        return;
    const float quad[12] = {lo[0], y, lo[1], hi[0], y, lo[1], hi[0], y, hi[1], lo[0], y, hi[1]};
    glBindBuffer(GL_ARRAY_BUFFER, fx->ground_buffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof quad, quad);
    glUseProgram(programs->ground);
    render_effects_uniforms(fx, programs->ground, ef);
    glUniformMatrix4fv(glGetUniformLocation(programs->ground, "u_view_proj"), 1, GL_FALSE, ef->view_proj);
    glUniform3fv(glGetUniformLocation(programs->ground, "u_center"), 1, ef->center);
    glUniform1f(glGetUniformLocation(programs->ground, "u_extent"), extent);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glBindVertexArray(fx->ground_vao);
    glDrawArrays(GL_TRIANGLE_FAN, 0, 4);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

/* Limits drawing to the pixels the scene's sphere (its bounding cube) covers, widened by a pixel;
 * false when it covers none. The whole view when a corner lies behind the eye. */
static bool scissor_to_scene(const render_effect_frame *ef)
{
    float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int k = 0; k < 8; k++) {
        vec4 p = {ef->center[0] + (k & 1 ? ef->radius : -ef->radius),
                  ef->center[1] + (k & 2 ? ef->radius : -ef->radius),
                  ef->center[2] + (k & 4 ? ef->radius : -ef->radius), 1.0f},
             c;
        glm_mat4_mulv((vec4 *)ef->view_proj, p, c);
        if (c[3] <= 1e-6f)
            return true; /* no scissor */
        x0 = fminf(x0, c[0] / c[3]), x1 = fmaxf(x1, c[0] / c[3]);
        y0 = fminf(y0, c[1] / c[3]), y1 = fmaxf(y1, c[1] / c[3]);
    }
    int px0 = (int)floorf((x0 * 0.5f + 0.5f) * (float)ef->width) - 1,
        px1 = (int)ceilf((x1 * 0.5f + 0.5f) * (float)ef->width) + 1;
    int py0 = (int)floorf((y0 * 0.5f + 0.5f) * (float)ef->height) - 1,
        py1 = (int)ceilf((y1 * 0.5f + 0.5f) * (float)ef->height) + 1;
    px0 = px0 < 0 ? 0 : px0, py0 = py0 < 0 ? 0 : py0;
    px1 = px1 > ef->width ? ef->width : px1, py1 = py1 > ef->height ? ef->height : py1;
    if (px1 <= px0 || py1 <= py0)
        return false;
    glEnable(GL_SCISSOR_TEST);
    glScissor(px0, py0, px1 - px0, py1 - py0);
    return true;
}

void render_effects_outline(const render_effects *fx, const render_programs *programs, const render_effect_frame *ef)
{
    if (!scissor_to_scene(ef))
        return;
    GLuint p = programs->outline;
    glUseProgram(p);
    glActiveTexture(GL_TEXTURE10);
    glBindTexture(GL_TEXTURE_2D, fx->depth_texture);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_depth"), 10);
    glUniform2f(glGetUniformLocation(p, "u_viewport"), (float)ef->width, (float)ef->height);
    glUniform2f(glGetUniformLocation(p, "u_planes"), ef->near_plane, ef->far_plane);
    glUniform1i(glGetUniformLocation(p, "u_ortho"), ef->orthographic);
    glUniform4f(glGetUniformLocation(p, "u_color"), 0.02f, 0.02f, 0.03f, 0.9f);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glBindVertexArray(fx->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
}

bool render_effects_begin_fxaa(render_effects *fx, int width, int height)
{
    if (!fx->aa_fbo || fx->aa_width != width || fx->aa_height != height) {
        glDeleteFramebuffers(1, &fx->aa_fbo);
        glDeleteTextures(1, &fx->aa_color);
        glDeleteRenderbuffers(1, &fx->aa_depth);
        fx->aa_color = make_texture(GL_RGBA8, width, height, GL_RGBA, GL_UNSIGNED_BYTE, NULL, GL_LINEAR);
        glGenRenderbuffers(1, &fx->aa_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, fx->aa_depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        glBindRenderbuffer(GL_RENDERBUFFER, 0);
        glGenFramebuffers(1, &fx->aa_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fx->aa_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fx->aa_color, 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, fx->aa_depth);
        fx->aa_width = width, fx->aa_height = height;
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            glDeleteFramebuffers(1, &fx->aa_fbo);
            fx->aa_fbo = 0;
            return false;
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fx->aa_fbo);
    return true;
}

void render_effects_fxaa(const render_effects *fx, const render_programs *programs, GLuint target, int width,
                         int height)
{
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target);
    glViewport(0, 0, width, height);
    glUseProgram(programs->fxaa);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, fx->aa_color);
    glUniform1i(glGetUniformLocation(programs->fxaa, "u_color"), 0);
    glUniform2f(glGetUniformLocation(programs->fxaa, "u_texel"), 1.0f / (float)width, 1.0f / (float)height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glBindVertexArray(fx->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindTexture(GL_TEXTURE_2D, 0);
    glEnable(GL_DEPTH_TEST);
}
