/* sinew-view's settings: ~/.config/sinew/settings.ini (GKeyFile; $XDG_CONFIG_HOME is
 * honoured), read at start before the command line (which overrides it for that run: an option
 * given there is not saved unless changed in the window) and written when the window closes.
 *
 *   [display]  every display option by its `sinew render` name: grid=on, shading=flat, ...
 *   [window]   width, height
 *   [files]    last-folder (where Open… starts), recent (the last 10 files opened)
 *   [view]     key-map (sinew or blender), samples (anti-aliasing: 1 off, 2..16; default 4), hdri
 *              (the environment file for physically based shading; empty: the built-in studio),
 *              follow (true: the camera follows the model)
 *   [keys]     action=key, keys as GDK names them (space, Left, F1, a, ...): the keys rebound
 *              (earlier versions wrote every key; meshes=h, H's old default, is read as unset)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer.h"

static const view_key default_keys[ACTION_COUNT] = {
    [ACTION_PLAY] = {"play", NULL, "space", 0},
    [ACTION_PREVIOUS_FRAME] = {"previous-frame", NULL, "Left", 0},
    [ACTION_NEXT_FRAME] = {"next-frame", NULL, "Right", 0},
    [ACTION_FIRST] = {"first-frame", NULL, "Home", 0},
    [ACTION_LAST] = {"last-frame", NULL, "End", 0},
    [ACTION_FRAME_ALL] = {"frame-all", NULL, "f", 0},
    [ACTION_CAMERA_MODE] = {"camera-mode", NULL, "Tab", 0},
    [ACTION_MATERIALS] = {"materials", "materials", "1", 0},
    [ACTION_LIGHTING] = {"lighting", "lighting", "2", 0},
    [ACTION_SHADING] = {"shading", NULL, "3", 0},
    [ACTION_WIREFRAME] = {"wireframe", "wireframe", "4", 0},
    [ACTION_SKELETON] = {"skeleton", "skeleton", "5", 0},
    [ACTION_NORMALS] = {"normals", "normals", "6", 0},
    [ACTION_GRID] = {"grid", "grid", "7", 0},
    [ACTION_AXES] = {"axes", "axes", "8", 0},
    [ACTION_JOINT_NAMES] = {"joint-names", "joint-names", "9", 0},
    [ACTION_JOINT_AXES] = {"joint-axes", "joint-axes", "0", 0},
    [ACTION_MUSCLES] = {"muscles", "muscles", "m", 0},
    [ACTION_MESHES] = {"meshes", "meshes", "H", 0},
    [ACTION_SKIN_METHOD] = {"skinning-method", NULL, "k", 0},
    [ACTION_CROWD] = {"crowd", NULL, "c", 0},
    [ACTION_PREVIOUS_KEY] = {"previous-key", NULL, "Down", 0},
    [ACTION_NEXT_KEY] = {"next-key", NULL, "Up", 0},
    [ACTION_HELP] = {"help", NULL, "h", 0},
    [ACTION_SCREENSHOT] = {"screenshot", NULL, "F12", 0},
    [ACTION_VIEW_FRONT] = {"view-front", NULL, "KP_1", 0},
    [ACTION_VIEW_SIDE] = {"view-side", NULL, "KP_3", 0},
    [ACTION_VIEW_TOP] = {"view-top", NULL, "KP_7", 0},
    [ACTION_ORTHOGRAPHIC] = {"orthographic", NULL, "KP_5", 0},
    [ACTION_RESET_VIEW] = {"reset-view", NULL, "r", 0},
    [ACTION_PREVIOUS_FILE] = {"previous-file", NULL, "Page_Up", 0},
    [ACTION_NEXT_FILE] = {"next-file", NULL, "Page_Down", 0},
    [ACTION_RECORD] = {"record", NULL, "F9", 0},
    [ACTION_FOLLOW] = {"follow", NULL, "t", 0},
    [ACTION_FORWARD] = {"fly-forward", NULL, "w", 0},
    [ACTION_BACK] = {"fly-back", NULL, "s", 0},
    [ACTION_LEFT] = {"fly-left", NULL, "a", 0},
    [ACTION_RIGHT] = {"fly-right", NULL, "d", 0},
    [ACTION_DOWN] = {"fly-down", NULL, "q", 0},
    [ACTION_UP] = {"fly-up", NULL, "e", 0},
};

/* Where Blender's habits differ from sinew's keys (the others are the same). */
static const char *blender_key(int action)
{
    switch (action) {
    case ACTION_FRAME_ALL:
        return "Home"; /* View All */
    case ACTION_FIRST:
        return "KP_Home"; /* and Shift+Left, as Blender's jump to start */
    case ACTION_LAST:
        return "KP_End"; /* and Shift+Right */
    default:
        return NULL;
    }
}

static guint default_key_of(view_key_map map, int action)
{
    const char *name =
        map == KEY_MAP_BLENDER && blender_key(action) ? blender_key(action) : default_keys[action].default_key;
    return gdk_keyval_from_name(name);
}

const char *const KEY_MAP_NAMES[KEY_MAP_COUNT] = {"sinew", "blender"};

void settings_set_key_map(viewer *v, view_key_map map)
{
    for (int a = 0; a < ACTION_COUNT; a++)
        if (v->keys[a].key == default_key_of(v->key_map, a))
            v->keys[a].key = default_key_of(map, a);
    v->key_map = map;
}

int settings_option_index(const char *name)
{
    int i = 0;
    for (const char *const *n = sinew_render_option_names(); *n && i < 32; n++, i++)
        if (strcmp(*n, name) == 0)
            return i;
    return -1;
}

void settings_option_changed(viewer *v, const char *name)
{
    int i = settings_option_index(name);
    if (i >= 0)
        v->overridden[i] = false;
    if (strcmp(name, "skeleton") == 0)
        v->skeleton_shown_for_file = false; /* the user's choice from now on */
}

void settings_defaults(viewer *v)
{
    for (int a = 0; a < ACTION_COUNT; a++) {
        v->keys[a] = default_keys[a];
        v->keys[a].key = gdk_keyval_from_name(default_keys[a].default_key);
    }
    v->width = 1200;
    v->height = 760;
    v->samples = 4;
    const char *config = g_get_user_config_dir();
    v->settings_path = g_build_filename(config, "sinew", "settings.ini", NULL);
}

void settings_load(viewer *v)
{
    GKeyFile *file = g_key_file_new();
    GError *error = NULL;
    if (!g_key_file_load_from_file(file, v->settings_path, G_KEY_FILE_NONE, &error)) {
        if (!g_error_matches(error, G_FILE_ERROR, G_FILE_ERROR_NOENT))
            fprintf(stderr, "sinew-view: %s: %s (defaults used)\n", v->settings_path, error->message);
        g_error_free(error);
        g_key_file_free(file);
        return;
    }
    for (const char *const *n = sinew_render_option_names(); *n; n++) {
        char *value = g_key_file_get_string(file, "display", *n, NULL);
        sinew_error e = {0};
        if (value && sinew_render_option_set(&v->options, *n, value, &e) != SINEW_OK)
            fprintf(stderr, "sinew-view: %s: [display] %s\n", v->settings_path, e.message);
        g_free(value);
    }
    int w = g_key_file_get_integer(file, "window", "width", NULL),
        h = g_key_file_get_integer(file, "window", "height", NULL);
    if (w >= 200 && h >= 150 && w <= 16384 && h <= 16384)
        v->width = w, v->height = h;
    char **recent = g_key_file_get_string_list(file, "files", "recent", NULL, NULL);
    for (int i = 0; recent && recent[i] && i < 10; i++)
        v->recent[i] = g_strdup(recent[i]);
    g_strfreev(recent);
    char *folder = g_key_file_get_string(file, "files", "last-folder", NULL);
    if (folder) {
        g_free(v->last_folder);
        v->last_folder = folder;
    }
    char *map = g_key_file_get_string(file, "view", "key-map", NULL);
    for (int m = 0; map && m < KEY_MAP_COUNT; m++)
        if (g_ascii_strcasecmp(map, KEY_MAP_NAMES[m]) == 0)
            settings_set_key_map(v, (view_key_map)m);
    g_free(map);
    GError *samples_error = NULL;
    int samples = g_key_file_get_integer(file, "view", "samples", &samples_error);
    if (!samples_error && samples >= 1 && samples <= 16)
        v->samples = samples;
    g_clear_error(&samples_error);
    GError *follow_error = NULL;
    gboolean follow = g_key_file_get_boolean(file, "view", "follow", &follow_error);
    if (!follow_error)
        v->look.follow = follow;
    g_clear_error(&follow_error);
    char *hdri = g_key_file_get_string(file, "view", "hdri", NULL);
    if (hdri && hdri[0])
        v->hdri = hdri;
    else
        g_free(hdri);
    for (int a = 0; a < ACTION_COUNT; a++) {
        char *name = g_key_file_get_string(file, "keys", v->keys[a].action, NULL);
        /* files of earlier versions hold every key; an old default moved since is not the user's choice */
        if (name && a == ACTION_MESHES && strcmp(name, "h") == 0) {
            g_free(name);
            continue;
        }
        if (!name)
            continue;
        guint key = gdk_keyval_from_name(name);
        if (key == GDK_KEY_VoidSymbol || key == 0)
            fprintf(stderr, "sinew-view: %s: [keys] %s: no key named \"%s\" (kept %s)\n", v->settings_path,
                    v->keys[a].action, name, gdk_keyval_name(v->keys[a].key));
        else
            v->keys[a].key = key;
        g_free(name);
    }
    g_key_file_free(file);
}

bool settings_save(viewer *v)
{
    GKeyFile *file = g_key_file_new();
    g_key_file_load_from_file(file, v->settings_path, G_KEY_FILE_KEEP_COMMENTS, NULL); /* keep other keys */
    int index = 0;
    for (const char *const *n = sinew_render_option_names(); *n; n++, index++) {
        char value[64];
        if (index < 32 && v->overridden[index])
            continue; /* given on the command line for this run only */
        if (sinew_render_option_get(&v->options, *n, value, sizeof value, NULL) == SINEW_OK)
            g_key_file_set_string(file, "display", *n, value);
    }
    g_key_file_set_integer(file, "window", "width", v->width);
    g_key_file_set_integer(file, "window", "height", v->height);
    if (v->last_folder)
        g_key_file_set_string(file, "files", "last-folder", v->last_folder);
    int recent = 0;
    while (recent < 10 && v->recent[recent])
        recent++;
    if (recent)
        g_key_file_set_string_list(file, "files", "recent", (const char *const *)v->recent, (gsize)recent);
    if (!v->key_map_given)
        g_key_file_set_string(file, "view", "key-map", KEY_MAP_NAMES[v->key_map]);
    if (!v->samples_given)
        g_key_file_set_integer(file, "view", "samples", v->samples);
    if (!v->hdri_given)
        g_key_file_set_string(file, "view", "hdri", v->hdri ? v->hdri : "");
    if (!v->look.follow_given)
        g_key_file_set_boolean(file, "view", "follow", v->look.follow);
    /* only the keys the user rebound: the others follow the defaults of later versions */
    for (int a = 0; a < ACTION_COUNT; a++)
        if (v->keys[a].key == default_key_of(v->key_map, a))
            g_key_file_remove_key(file, "keys", v->keys[a].action, NULL);
        else
            g_key_file_set_string(file, "keys", v->keys[a].action, gdk_keyval_name(v->keys[a].key));
    char *dir = g_path_get_dirname(v->settings_path);
    g_mkdir_with_parents(dir, 0700);
    g_free(dir);
    GError *error = NULL;
    bool ok = g_key_file_save_to_file(file, v->settings_path, &error);
    if (!ok) {
        fprintf(stderr, "sinew-view: %s: cannot save the settings: %s\n", v->settings_path, error->message);
        g_error_free(error);
    }
    g_key_file_free(file);
    return ok;
}

int settings_action_for_key(const viewer *v, guint key)
{
    guint lower = gdk_keyval_to_lower(key);
    for (int a = 0; a < ACTION_COUNT; a++) /* as bound first (Shift+H and H differ), then by the lower case */
        if (v->keys[a].key == key)
            return a;
    for (int a = 0; a < ACTION_COUNT; a++)
        if (v->keys[a].key == lower)
            return a;
    return -1;
}
