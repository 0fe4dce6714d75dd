/* sinew-view's side panel: the hierarchy (nodes and joints with a search box; selecting a
 * joint highlights its bone, shows its weight heat map and its local and world transform;
 * each mesh can be hidden), the display switches (each also on a key), the camera mode,
 * and the log of the current file's import warnings and of errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "viewer.h"

/* ---- hierarchy ---------------------------------------------------------------------------- */

static gboolean filter_row(GtkListBoxRow *row, gpointer data)
{
    viewer *v = data;
    const char *text = gtk_editable_get_text(GTK_EDITABLE(v->node_search));
    if (!text[0])
        return TRUE;
    int node = GPOINTER_TO_INT(g_object_get_data(G_OBJECT(row), "node"));
    if (!v->scene.model || node < 0 || (uint32_t)node >= v->scene.model->node_count)
        return FALSE;
    char *name = g_utf8_casefold(v->scene.model->node_names[node], -1), *want = g_utf8_casefold(text, -1);
    gboolean match = strstr(name, want) != NULL;
    g_free(name);
    g_free(want);
    return match;
}

static void on_search(GtkSearchEntry *entry, gpointer data)
{
    (void)entry;
    viewer *v = data;
    gtk_list_box_invalidate_filter(GTK_LIST_BOX(v->node_list));
}

static GtkListBoxRow *row_of_node(viewer *v, int32_t node);

static void on_hide_mesh(GtkCheckButton *check, gpointer data)
{
    viewer *v = data;
    int instance = GPOINTER_TO_INT(g_object_get_data(G_OBJECT(check), "instance"));
    if (v->hidden && instance >= 0 && (uint32_t)instance < v->scene.model->instance_count) {
        v->hidden[instance] = !gtk_check_button_get_active(check);
        view_redraw(v);
    }
}

void panels_select(viewer *v, int32_t node)
{
    v->selected = node;
    if (v->node_list && node >= 0) { /* the row too, when chosen elsewhere (--select) */
        GtkListBoxRow *row = row_of_node(v, node);
        bool was = v->updating;
        v->updating = true;
        if (row && gtk_list_box_get_selected_row(GTK_LIST_BOX(v->node_list)) != row)
            gtk_list_box_select_row(GTK_LIST_BOX(v->node_list), row);
        v->updating = was;
    }
    bool joint = node >= 0 && sinew_model_node_is_joint(v->scene.model, (uint32_t)node);
    v->options.select_joint = joint;
    v->options.selected_joint = joint ? (uint32_t)node : 0;
    v->options.heatmap = joint && gtk_check_button_get_active(GTK_CHECK_BUTTON(v->heatmap_check));
    v->options.heatmap_joint = v->options.heatmap ? (uint32_t)node : 0;
    if (node >= 0)
        view_pose(v);
    panels_frame_drawn(v);
    view_redraw(v);
}

static void on_row_selected(GtkListBox *box, GtkListBoxRow *row, gpointer data)
{
    (void)box;
    viewer *v = data;
    if (v->updating)
        return;
    panels_select(v, row ? GPOINTER_TO_INT(g_object_get_data(G_OBJECT(row), "node")) : -1);
}

static void on_heatmap(GtkCheckButton *check, gpointer data)
{
    (void)check;
    viewer *v = data;
    panels_select(v, v->selected);
}

static void add_node_row(viewer *v, uint32_t node, uint32_t depth)
{
    const sinew_model *m = v->scene.model;
    GtkWidget *box = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 4);
    gtk_widget_set_margin_start(box, 4 + 12 * (int)depth);
    bool joint = sinew_model_node_is_joint(m, node);
    GtkWidget *icon = gtk_label_new(joint ? "◆" : "○");
    gtk_widget_set_tooltip_text(icon, joint ? "joint" : "node");
    gtk_box_append(GTK_BOX(box), icon);
    GtkWidget *name = gtk_label_new(m->node_names[node]);
    gtk_label_set_xalign(GTK_LABEL(name), 0.0f);
    gtk_label_set_ellipsize(GTK_LABEL(name), PANGO_ELLIPSIZE_END);
    gtk_widget_set_hexpand(name, TRUE);
    gtk_box_append(GTK_BOX(box), name);
    gtk_list_box_append(GTK_LIST_BOX(v->node_list), box);
    GtkListBoxRow *row = GTK_LIST_BOX_ROW(gtk_widget_get_parent(box));
    g_object_set_data(G_OBJECT(row), "node", GINT_TO_POINTER((int)node));
    /* its meshes below it, each with a check that shows or hides it */
    for (uint32_t i = 0; i < m->instance_count; i++) {
        if (m->instances[i].node != node)
            continue;
        GtkWidget *check = gtk_check_button_new_with_label(m->meshes[m->instances[i].mesh].name);
        gtk_check_button_set_active(GTK_CHECK_BUTTON(check), !v->hidden[i]);
        gtk_widget_set_tooltip_text(check, "show this mesh");
        gtk_widget_set_margin_start(check, 16 + 12 * (int)depth);
        g_object_set_data(G_OBJECT(check), "instance", GINT_TO_POINTER((int)i));
        g_signal_connect(check, "toggled", G_CALLBACK(on_hide_mesh), v);
        gtk_list_box_append(GTK_LIST_BOX(v->node_list), check);
        GtkWidget *mesh_row = gtk_widget_get_parent(check);
        gtk_list_box_row_set_selectable(GTK_LIST_BOX_ROW(mesh_row), FALSE);
        g_object_set_data(G_OBJECT(mesh_row), "node", GINT_TO_POINTER((int)node));
        g_object_set_data(G_OBJECT(mesh_row), "mesh-row", GINT_TO_POINTER(1));
    }
}

/* The hierarchy row of a node (rows of meshes sit between node rows). */
static GtkListBoxRow *row_of_node(viewer *v, int32_t node)
{
    for (GtkWidget *row = gtk_widget_get_first_child(v->node_list); row; row = gtk_widget_get_next_sibling(row))
        if (GTK_IS_LIST_BOX_ROW(row) && !g_object_get_data(G_OBJECT(row), "mesh-row") &&
            GPOINTER_TO_INT(g_object_get_data(G_OBJECT(row), "node")) == node)
            return GTK_LIST_BOX_ROW(row);
    return NULL;
}

static void format_transform(const char *title, const sinew_mat4 *m, char *out, size_t size)
{
    sinew_transform t;
    sinew_mat4_decompose(m, &t);
    /* Euler angles (degrees, X then Y then Z) of the rotation, for reading */
    float x = t.rotation[0], y = t.rotation[1], z = t.rotation[2], w = t.rotation[3];
    double ex = atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
    double sy = 2.0 * (w * y - z * x);
    double ey = fabs(sy) >= 1.0 ? copysign(M_PI / 2, sy) : asin(sy);
    double ez = atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
    snprintf(out, size,
             "<b>%s</b>\ntranslation  %.4f  %.4f  %.4f\nrotation  %.4f  %.4f  %.4f  %.4f\n"
             "  (XYZ %.1f°  %.1f°  %.1f°)\nscale  %.4f  %.4f  %.4f\n",
             title, t.translation[0], t.translation[1], t.translation[2], x, y, z, w, ex * 180.0 / M_PI,
             ey * 180.0 / M_PI, ez * 180.0 / M_PI, t.scale[0], t.scale[1], t.scale[2]);
}

void panels_frame_drawn(viewer *v)
{
    if (!v->transform_label)
        return;
    if (v->selected < 0 || !v->scene.model || (uint32_t)v->selected >= v->scene.model->node_count) {
        gtk_label_set_markup(GTK_LABEL(v->transform_label), "<i>Select a node to see its transforms.</i>");
        return;
    }
    const sinew_mat4 *world = &v->scene.worlds[v->selected];
    sinew_mat4 local = *world;
    int32_t parent = v->scene.model->node_parents[v->selected];
    if (parent >= 0) { /* local = inverse(parent world) * world */
        mat4 inverse;
        glm_mat4_inv((vec4 *)v->scene.worlds[parent].m, inverse);
        glm_mat4_mul(inverse, (vec4 *)world->m, (vec4 *)local.m);
    }
    char a[512], b[512], text[1200];
    format_transform("local", &local, a, sizeof a);
    format_transform("world", world, b, sizeof b);
    char *name = g_markup_escape_text(v->scene.model->node_names[v->selected], -1);
    snprintf(text, sizeof text, "<b><big>%s</big></b>%s\n%s\n%s", name,
             sinew_model_node_is_joint(v->scene.model, (uint32_t)v->selected) ? "  (joint)" : "", a, b);
    g_free(name);
    gtk_label_set_markup(GTK_LABEL(v->transform_label), text);
}

/* ---- display --------------------------------------------------------------------------------- */

static void on_option(GtkCheckButton *check, gpointer data)
{
    viewer *v = data;
    if (v->updating)
        return;
    const char *name = g_object_get_data(G_OBJECT(check), "option");
    settings_option_changed(v, name);
    sinew_render_option_set(&v->options, name, gtk_check_button_get_active(check) ? "on" : "off", NULL);
    view_redraw(v);
}

static void on_shading(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    if (v->updating)
        return;
    static const char *const names[] = {"phong", "gouraud", "flat", "pbr"};
    guint i = gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown));
    settings_option_changed(v, "shading");
    if (i < 4)
        sinew_render_option_set(&v->options, "shading", names[i], NULL);
    view_redraw(v);
}

static void on_skin_method(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    if (v->updating)
        return;
    static const char *const methods[] = {"file", "lbs", "dqs"};
    guint i = gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown));
    settings_option_changed(v, "skinning-method");
    sinew_render_option_set(&v->options, "skinning-method", methods[i < 3 ? i : 0], NULL);
    view_redraw(v);
}

static void on_crowd(GtkCheckButton *check, gpointer data)
{
    viewer *v = data;
    if (!v->updating)
        view_toggle_crowd(v, gtk_check_button_get_active(check));
}

static void on_follow(GtkCheckButton *check, gpointer data)
{
    viewer *v = data;
    if (!v->updating)
        view_set_follow(v, gtk_check_button_get_active(check));
}

static void on_camera_mode(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    if (v->updating)
        return;
    sinew_camera_set_mode(&v->look.camera,
                          gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown)) ? SINEW_CAMERA_FLY : SINEW_CAMERA_ORBIT);
    view_redraw(v);
}

static void on_key_map(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    if (v->updating)
        return;
    guint i = gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown));
    if (i < KEY_MAP_COUNT) {
        settings_set_key_map(v, (view_key_map)i);
        v->key_map_given = false; /* chosen in the window: saved */
        panels_log(v, i == KEY_MAP_BLENDER ? "keys: Blender's (Home frames all, middle-drag orbits, shift-middle pans)"
                                           : "keys: sinew's (f frames all, drag orbits, shift-drag pans)");
    }
}

static const char *key_for_option(const viewer *v, const char *option)
{
    for (int a = 0; a < ACTION_COUNT; a++)
        if (v->keys[a].option && strcmp(v->keys[a].option, option) == 0)
            return gdk_keyval_name(v->keys[a].key);
    return NULL;
}

void panels_options_changed(viewer *v)
{
    v->updating = true;
    int i = 0;
    for (const char *const *n = sinew_render_option_names(); *n && i < 32; n++, i++) {
        char value[64];
        if (v->option_checks[i] && sinew_render_option_get(&v->options, *n, value, sizeof value, NULL) == SINEW_OK)
            gtk_check_button_set_active(GTK_CHECK_BUTTON(v->option_checks[i]), strcmp(value, "on") == 0);
    }
    if (v->shading_list)
        gtk_drop_down_set_selected(GTK_DROP_DOWN(v->shading_list), (guint)v->options.shading);
    if (v->skin_method_list)
        gtk_drop_down_set_selected(GTK_DROP_DOWN(v->skin_method_list),
                                   !v->options.skin_method_set                            ? 0
                                   : v->options.skin_method == SINEW_SKIN_DUAL_QUATERNION ? 2
                                                                                          : 1);
    if (v->camera_list)
        gtk_drop_down_set_selected(GTK_DROP_DOWN(v->camera_list), v->look.camera.mode == SINEW_CAMERA_FLY);
    v->updating = false;
}

static void on_blend_clip(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    if (v->updating)
        return;
    guint i = gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown));
    v->pose.blend_clip = i == 0 || i == GTK_INVALID_LIST_POSITION ? -1 : (int32_t)i - 1;
    view_apply_pose_ops(v);
}

static void on_blend_weight(GtkRange *range, gpointer data)
{
    viewer *v = data;
    if (v->updating)
        return;
    v->pose.blend_weight = gtk_range_get_value(range);
    view_apply_pose_ops(v);
}

static void on_cross_fade(GtkButton *button, gpointer data)
{
    (void)button;
    viewer *v = data;
    if (v->pose.blend_clip >= 0)
        v->pose.fade_from = (double)g_get_monotonic_time() * 1e-6; /* the tick moves the weight to 1 */
}

static void on_root_motion(GtkCheckButton *check, gpointer data)
{
    viewer *v = data;
    if (v->updating)
        return;
    v->pose.root_motion = gtk_check_button_get_active(check);
    view_apply_pose_ops(v);
}

static GtkWidget *display_page(viewer *v)
{
    GtkWidget *box = gtk_box_new(GTK_ORIENTATION_VERTICAL, 4);
    gtk_widget_set_margin_start(box, 8);
    gtk_widget_set_margin_top(box, 8);
    int i = 0;
    for (const char *const *n = sinew_render_option_names(); *n && i < 32; n++, i++) {
        if (!sinew_render_option_is_switch(*n))
            continue;
        const char *key = key_for_option(v, *n);
        char label[96];
        snprintf(label, sizeof label, key ? "%s   (%s)" : "%s", *n, key);
        GtkWidget *check = gtk_check_button_new_with_label(label);
        g_object_set_data(G_OBJECT(check), "option", (gpointer)*n);
        g_signal_connect(check, "toggled", G_CALLBACK(on_option), v);
        gtk_box_append(GTK_BOX(box), check);
        v->option_checks[i] = check;
    }
    char label[64];
    snprintf(label, sizeof label, "Shading   (%s cycles)", gdk_keyval_name(v->keys[ACTION_SHADING].key));
    gtk_box_append(GTK_BOX(box), gtk_label_new(label));
    static const char *const shadings[] = {"Phong", "Gouraud", "Flat", "Physically based", NULL};
    v->shading_list = gtk_drop_down_new_from_strings(shadings);
    g_signal_connect(v->shading_list, "notify::selected", G_CALLBACK(on_shading), v);
    gtk_box_append(GTK_BOX(box), v->shading_list);
    snprintf(label, sizeof label, "Skinning   (%s switches)", gdk_keyval_name(v->keys[ACTION_SKIN_METHOD].key));
    gtk_box_append(GTK_BOX(box), gtk_label_new(label));
    static const char *const methods[] = {"As the file says", "Linear blend", "Dual quaternion", NULL};
    v->skin_method_list = gtk_drop_down_new_from_strings(methods);
    g_signal_connect(v->skin_method_list, "notify::selected", G_CALLBACK(on_skin_method), v);
    gtk_box_append(GTK_BOX(box), v->skin_method_list);
    char crowd[64];
    snprintf(crowd, sizeof crowd, "crowd of %u   (%s)", v->crowd_size, gdk_keyval_name(v->keys[ACTION_CROWD].key));
    v->crowd_check = gtk_check_button_new_with_label(crowd);
    gtk_check_button_set_active(GTK_CHECK_BUTTON(v->crowd_check), v->crowd_on);
    g_signal_connect(v->crowd_check, "toggled", G_CALLBACK(on_crowd), v);
    gtk_box_append(GTK_BOX(box), v->crowd_check);
    snprintf(label, sizeof label, "Camera   (%s switches)", gdk_keyval_name(v->keys[ACTION_CAMERA_MODE].key));
    gtk_box_append(GTK_BOX(box), gtk_label_new(label));
    static const char *const cameras[] = {"Orbit: drag, shift-drag, wheel", "Fly: WASD, Q/E, right-drag", NULL};
    v->camera_list = gtk_drop_down_new_from_strings(cameras);
    g_signal_connect(v->camera_list, "notify::selected", G_CALLBACK(on_camera_mode), v);
    gtk_box_append(GTK_BOX(box), v->camera_list);
    snprintf(label, sizeof label, "follow the model   (%s)", gdk_keyval_name(v->keys[ACTION_FOLLOW].key));
    v->look.follow_check = gtk_check_button_new_with_label(label);
    gtk_check_button_set_active(GTK_CHECK_BUTTON(v->look.follow_check), v->look.follow);
    gtk_widget_set_tooltip_text(
        v->look.follow_check,
        "The camera moves over the ground with the clip's root (a capture's hips): a capture that walks away "
        "stays in view");
    g_signal_connect(v->look.follow_check, "toggled", G_CALLBACK(on_follow), v);
    gtk_box_append(GTK_BOX(box), v->look.follow_check);
    gtk_box_append(GTK_BOX(box), gtk_label_new("Keys and mouse"));
    static const char *const maps[] = {"sinew", "Blender", NULL};
    v->key_map_list = gtk_drop_down_new_from_strings(maps);
    gtk_drop_down_set_selected(GTK_DROP_DOWN(v->key_map_list), (guint)v->key_map);
    g_signal_connect(v->key_map_list, "notify::selected", G_CALLBACK(on_key_map), v);
    gtk_box_append(GTK_BOX(box), v->key_map_list);
    /* blending: a second clip, its weight, a cross-fade, root motion */
    gtk_box_append(GTK_BOX(box), gtk_label_new("Blend with   (ctrl-drag: IK to the selected joint)"));
    v->pose.blend_list = gtk_drop_down_new(NULL, NULL);
    g_signal_connect(v->pose.blend_list, "notify::selected", G_CALLBACK(on_blend_clip), v);
    gtk_box_append(GTK_BOX(box), v->pose.blend_list);
    GtkWidget *row = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 4);
    v->pose.blend_scale = gtk_scale_new_with_range(GTK_ORIENTATION_HORIZONTAL, 0.0, 1.0, 0.01);
    gtk_widget_set_hexpand(v->pose.blend_scale, TRUE);
    gtk_scale_set_draw_value(GTK_SCALE(v->pose.blend_scale), TRUE);
    g_signal_connect(v->pose.blend_scale, "value-changed", G_CALLBACK(on_blend_weight), v);
    gtk_box_append(GTK_BOX(row), v->pose.blend_scale);
    GtkWidget *fade = gtk_button_new_with_label("Cross-fade");
    gtk_widget_set_tooltip_text(fade, "Fade to the second clip over half a second");
    g_signal_connect(fade, "clicked", G_CALLBACK(on_cross_fade), v);
    gtk_box_append(GTK_BOX(row), fade);
    gtk_box_append(GTK_BOX(box), row);
    v->pose.root_motion_check = gtk_check_button_new_with_label("Root motion in place (path on the ground)");
    gtk_check_button_set_active(GTK_CHECK_BUTTON(v->pose.root_motion_check), v->pose.root_motion);
    g_signal_connect(v->pose.root_motion_check, "toggled", G_CALLBACK(on_root_motion), v);
    gtk_box_append(GTK_BOX(box), v->pose.root_motion_check);
    panels_options_changed(v);
    return box;
}

void panels_clips_changed(viewer *v)
{
    if (!v->pose.blend_list)
        return;
    GtkStringList *names = gtk_string_list_new(NULL);
    gtk_string_list_append(names, "(none)");
    for (uint32_t i = 0; v->scene.model && i < v->scene.model->clip_count; i++)
        gtk_string_list_append(names, v->scene.model->clips[i].name ? v->scene.model->clips[i].name : "clip");
    v->updating = true;
    gtk_drop_down_set_model(GTK_DROP_DOWN(v->pose.blend_list), G_LIST_MODEL(names));
    gtk_drop_down_set_selected(GTK_DROP_DOWN(v->pose.blend_list), 0);
    v->updating = false;
    g_object_unref(names);
    v->pose.blend_clip = -1;
}

/* ---- shape keys ------------------------------------------------------------------------------ */

/* A slider moved by hand: the channel's weight is the slider's from now on (its check on). */
static void on_shape_scale(GtkRange *range, gpointer data)
{
    viewer *v = data;
    if (v->updating)
        return;
    uint32_t c = GPOINTER_TO_UINT(g_object_get_data(G_OBJECT(range), "channel"));
    v->updating = true;
    gtk_check_button_set_active(GTK_CHECK_BUTTON(v->shape_checks[c]), TRUE);
    v->updating = false;
    app_scene_override_weight(&v->scene, c, (float)gtk_range_get_value(range));
    if (view_pose(v))
        panels_weights_changed(v);
    view_redraw(v);
}

/* The check: on, the slider's value holds; off, the clip's weight again. */
static void on_shape_check(GtkCheckButton *check, gpointer data)
{
    viewer *v = data;
    if (v->updating)
        return;
    uint32_t c = GPOINTER_TO_UINT(g_object_get_data(G_OBJECT(check), "channel"));
    bool on = gtk_check_button_get_active(check);
    app_scene_override_weight(&v->scene, c, on ? (float)gtk_range_get_value(GTK_RANGE(v->shape_scales[c])) : NAN);
    if (view_pose(v))
        panels_weights_changed(v);
    view_redraw(v);
}

static void on_shape_reset(GtkButton *button, gpointer data)
{
    (void)button;
    viewer *v = data;
    for (uint32_t c = 0; c < v->shape_count; c++)
        app_scene_override_weight(&v->scene, c, NAN);
    if (view_pose(v))
        panels_weights_changed(v);
    view_redraw(v);
}

void panels_weights_changed(viewer *v)
{
    if (!v->shape_count || !v->scene.weights)
        return;
    v->updating = true;
    for (uint32_t c = 0; c < v->shape_count; c++) {
        bool by_hand = !isnan(v->scene.overrides[c]);
        gtk_check_button_set_active(GTK_CHECK_BUTTON(v->shape_checks[c]), by_hand);
        if (fabs(gtk_range_get_value(GTK_RANGE(v->shape_scales[c])) - v->scene.weights[c]) > 1e-6)
            gtk_range_set_value(GTK_RANGE(v->shape_scales[c]), v->scene.weights[c]);
    }
    v->updating = false;
}

bool panels_set_slider(viewer *v, const char *text)
{
    const char *eq = strrchr(text, '=');
    const sinew_model *m = v->scene.model;
    if (!eq || !m)
        return false;
    size_t len = (size_t)(eq - text);
    double w = atof(eq + 1);
    for (uint32_t c = 0; c < v->shape_count; c++) {
        char index[16];
        snprintf(index, sizeof index, "%u", c);
        if ((strlen(m->morph_channels[c].name) == len && strncmp(text, m->morph_channels[c].name, len) == 0) ||
            (strlen(index) == len && strncmp(text, index, len) == 0)) {
            gtk_range_set_value(GTK_RANGE(v->shape_scales[c]), w); /* through on_shape_scale, as a drag */
            return true;
        }
    }
    return false;
}

/* The range a channel's slider covers: 0..1, wider where its default or its clips' keys go
 * beyond (FBX in-betweens from -100 to 200 percent). */
static void channel_range(const sinew_model *m, uint32_t c, double *lo, double *hi)
{
    *lo = fmin(0.0, m->morph_channels[c].default_weight);
    *hi = fmax(1.0, m->morph_channels[c].default_weight);
    for (uint32_t k = 0; k < m->clip_count; k++)
        for (uint32_t t = 0; t < m->clips[k].weight_track_count; t++) {
            const sinew_weight_track *tr = &m->clips[k].weight_tracks[t];
            if (tr->channel != c || tr->keys.interp != SINEW_INTERP_LINEAR)
                continue;
            for (uint32_t i = 0; i < tr->keys.key_count; i++) {
                float w = m->clips[k].values[tr->keys.first_value + i];
                *lo = fmin(*lo, floor(w)), *hi = fmax(*hi, ceil(w));
            }
        }
}

/* Rows for every morph channel, under the meshes (and nodes) whose targets it drives. */
static void build_shape_keys(viewer *v)
{
    GtkWidget *child;
    while ((child = gtk_widget_get_first_child(v->shape_box)) != NULL)
        gtk_box_remove(GTK_BOX(v->shape_box), child);
    g_free(v->shape_checks);
    g_free(v->shape_scales);
    const sinew_model *m = v->scene.model;
    v->shape_count = m ? m->morph_channel_count : 0;
    v->shape_checks = g_new0(GtkWidget *, v->shape_count + 1);
    v->shape_scales = g_new0(GtkWidget *, v->shape_count + 1);
    if (!v->shape_count) {
        gtk_box_append(GTK_BOX(v->shape_box), gtk_label_new("This file has no morph targets (shape keys)."));
        return;
    }
    GtkWidget *reset = gtk_button_new_with_label("Reset: every weight from the clip");
    g_signal_connect(reset, "clicked", G_CALLBACK(on_shape_reset), v);
    gtk_box_append(GTK_BOX(v->shape_box), reset);
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_instance *in = &m->instances[i];
        const sinew_mesh *mesh = &m->meshes[in->mesh];
        if (!mesh->morph_channel_count || v->shape_checks[in->morph_first])
            continue;
        char *name = g_markup_escape_text(mesh->name, -1), *node = g_markup_escape_text(m->node_names[in->node], -1);
        char *title = g_strdup_printf("<b>%s</b>  (%s)", name, node);
        GtkWidget *header = gtk_label_new(NULL);
        gtk_label_set_markup(GTK_LABEL(header), title);
        g_free(title);
        g_free(name);
        g_free(node);
        gtk_label_set_xalign(GTK_LABEL(header), 0.0f);
        gtk_box_append(GTK_BOX(v->shape_box), header);
        for (uint32_t k = 0; k < mesh->morph_channel_count; k++) {
            uint32_t c = in->morph_first + k;
            if (c >= v->shape_count || v->shape_checks[c])
                continue;
            GtkWidget *row = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 4);
            GtkWidget *check = gtk_check_button_new_with_label(m->morph_channels[c].name);
            gtk_widget_set_tooltip_text(check, "On: the slider sets the weight. Off: the clip's weight.");
            gtk_widget_set_size_request(check, 120, -1);
            double lo, hi;
            channel_range(m, c, &lo, &hi);
            GtkWidget *scale = gtk_scale_new_with_range(GTK_ORIENTATION_HORIZONTAL, lo, hi, 0.01);
            gtk_scale_set_draw_value(GTK_SCALE(scale), TRUE);
            gtk_scale_set_digits(GTK_SCALE(scale), 2);
            gtk_widget_set_hexpand(scale, TRUE);
            g_object_set_data(G_OBJECT(check), "channel", GUINT_TO_POINTER(c));
            g_object_set_data(G_OBJECT(scale), "channel", GUINT_TO_POINTER(c));
            g_signal_connect(check, "toggled", G_CALLBACK(on_shape_check), v);
            g_signal_connect(scale, "value-changed", G_CALLBACK(on_shape_scale), v);
            gtk_box_append(GTK_BOX(row), check);
            gtk_box_append(GTK_BOX(row), scale);
            gtk_box_append(GTK_BOX(v->shape_box), row);
            v->shape_checks[c] = check;
            v->shape_scales[c] = scale;
        }
    }
    /* channels no instance shows (none in a well-formed file): rows all the same */
    for (uint32_t c = 0; c < v->shape_count; c++)
        if (!v->shape_checks[c]) {
            v->shape_checks[c] = gtk_check_button_new_with_label(m->morph_channels[c].name);
            v->shape_scales[c] = gtk_scale_new_with_range(GTK_ORIENTATION_HORIZONTAL, -1.0, 2.0, 0.01);
            g_object_set_data(G_OBJECT(v->shape_checks[c]), "channel", GUINT_TO_POINTER(c));
            g_object_set_data(G_OBJECT(v->shape_scales[c]), "channel", GUINT_TO_POINTER(c));
            g_signal_connect(v->shape_checks[c], "toggled", G_CALLBACK(on_shape_check), v);
            g_signal_connect(v->shape_scales[c], "value-changed", G_CALLBACK(on_shape_scale), v);
            gtk_box_append(GTK_BOX(v->shape_box), v->shape_checks[c]);
            gtk_box_append(GTK_BOX(v->shape_box), v->shape_scales[c]);
        }
    if (view_pose(v))
        panels_weights_changed(v);
}

/* ---- log ------------------------------------------------------------------------------------- */

void panels_log(viewer *v, const char *line)
{
    if (!v->log_view)
        return;
    GtkTextBuffer *buffer = gtk_text_view_get_buffer(GTK_TEXT_VIEW(v->log_view));
    GtkTextIter end;
    gtk_text_buffer_get_end_iter(buffer, &end);
    gtk_text_buffer_insert(buffer, &end, line, -1);
    gtk_text_buffer_insert(buffer, &end, "\n", -1);
}

/* ---- the panel -------------------------------------------------------------------------------- */

void panels_model_changed(viewer *v)
{
    if (!v->node_list)
        return;
    v->updating = true;
    GtkWidget *child;
    while ((child = gtk_widget_get_first_child(v->node_list)) != NULL)
        gtk_list_box_remove(GTK_LIST_BOX(v->node_list), child);
    /* in tree order: a node added after its siblings' subtrees (the demo's Staff, under Hand.R)
     * sits under its parent, not after the last row */
    uint32_t count = v->scene.model->node_count;
    uint32_t *order = g_new(uint32_t, count ? count : 1), *depth = g_new(uint32_t, count ? count : 1);
    count = app_tree_order(v->scene.model, order, depth);
    for (uint32_t i = 0; i < count; i++)
        add_node_row(v, order[i], depth[order[i]]);
    g_free(order);
    g_free(depth);
    v->updating = false;
    v->selected = -1;
    panels_select(v, -1);
    if (v->shape_box) {
        v->updating = true;
        build_shape_keys(v);
        v->updating = false;
    }
    char line[1024];
    snprintf(line, sizeof line, "%s: %u nodes, %u meshes, %u clips, %u warnings", v->scene.model->source,
             v->scene.model->node_count, v->scene.model->mesh_count, v->scene.model->clip_count,
             v->scene.model->warning_count);
    panels_log(v, line);
    for (uint32_t i = 0; i < v->scene.model->warning_count; i++) {
        snprintf(line, sizeof line, "%s: warning: %s", v->scene.model->source, v->scene.model->warnings[i]);
        panels_log(v, line);
    }
}

GtkWidget *panels_create(viewer *v)
{
    GtkWidget *notebook = gtk_notebook_new();
    gtk_widget_set_size_request(notebook, 300, -1);

    GtkWidget *tree = gtk_box_new(GTK_ORIENTATION_VERTICAL, 4);
    v->node_search = gtk_search_entry_new();
    g_signal_connect(v->node_search, "search-changed", G_CALLBACK(on_search), v);
    gtk_box_append(GTK_BOX(tree), v->node_search);
    v->node_list = gtk_list_box_new();
    gtk_list_box_set_filter_func(GTK_LIST_BOX(v->node_list), filter_row, v, NULL);
    g_signal_connect(v->node_list, "row-selected", G_CALLBACK(on_row_selected), v);
    GtkWidget *scroll = gtk_scrolled_window_new();
    gtk_scrolled_window_set_child(GTK_SCROLLED_WINDOW(scroll), v->node_list);
    gtk_widget_set_vexpand(scroll, TRUE);
    gtk_box_append(GTK_BOX(tree), scroll);
    v->heatmap_check = gtk_check_button_new_with_label("Weight heat map of the selected joint");
    gtk_check_button_set_active(GTK_CHECK_BUTTON(v->heatmap_check), TRUE);
    g_signal_connect(v->heatmap_check, "toggled", G_CALLBACK(on_heatmap), v);
    gtk_box_append(GTK_BOX(tree), v->heatmap_check);
    v->transform_label = gtk_label_new("");
    gtk_label_set_xalign(GTK_LABEL(v->transform_label), 0.0f);
    gtk_label_set_selectable(GTK_LABEL(v->transform_label), TRUE);
    gtk_widget_set_margin_start(v->transform_label, 6);
    gtk_box_append(GTK_BOX(tree), v->transform_label);
    gtk_notebook_append_page(GTK_NOTEBOOK(notebook), tree, gtk_label_new("Hierarchy"));

    gtk_notebook_append_page(GTK_NOTEBOOK(notebook), display_page(v), gtk_label_new("Display"));

    v->shape_box = gtk_box_new(GTK_ORIENTATION_VERTICAL, 4);
    gtk_widget_set_margin_start(v->shape_box, 8);
    gtk_widget_set_margin_end(v->shape_box, 8);
    gtk_widget_set_margin_top(v->shape_box, 8);
    GtkWidget *shape_scroll = gtk_scrolled_window_new();
    gtk_scrolled_window_set_child(GTK_SCROLLED_WINDOW(shape_scroll), v->shape_box);
    gtk_notebook_append_page(GTK_NOTEBOOK(notebook), shape_scroll, gtk_label_new("Shape keys"));

    v->log_view = gtk_text_view_new();
    gtk_text_view_set_editable(GTK_TEXT_VIEW(v->log_view), FALSE);
    gtk_text_view_set_wrap_mode(GTK_TEXT_VIEW(v->log_view), GTK_WRAP_WORD_CHAR);
    gtk_text_view_set_monospace(GTK_TEXT_VIEW(v->log_view), TRUE);
    GtkWidget *log_scroll = gtk_scrolled_window_new();
    gtk_scrolled_window_set_child(GTK_SCROLLED_WINDOW(log_scroll), v->log_view);
    gtk_notebook_append_page(GTK_NOTEBOOK(notebook), log_scroll, gtk_label_new("Log"));
    return notebook;
}
