/* Clip 0 fading into clip 1 while JOINT reaches by IK a quarter of the way to its grandparent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sinew/sinew.h>
int main(int argc, char **argv)
{
    sinew_model *m = NULL;
    sinew_error e = {0};
    if (argc != 3 || sinew_import(&(sinew_import_desc){.path = argv[1]}, &m, &e) || m->clip_count < 2)
        return fprintf(stderr, "usage: crossfade MODEL JOINT (a model with two clips) %s\n", e.message), 2;
    sinew_clip_layout *clips[2];
    for (int i = 0; i < 2; i++) /* each clip laid out once, shared by every character that plays it */
        sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = m, .clip = &m->clips[i]}, &clips[i], &e);
    sinew_character_layer layers[2] = {{.layout = clips[0], .weight = 1}, {.layout = clips[1]}};
    sinew_character_ik ik = {.end = (uint32_t)sinew_model_find_joint(m, argv[2])};
    sinew_character_desc d = {.model = m, .layers = layers, .layer_count = 2, .ik = &ik, .ik_count = 1};
    size_t size = sinew_character_size(&d);
    void *memory = malloc(size);
    sinew_mat4 *w = malloc(m->node_count * sizeof *w);
    sinew_character *c;
    sinew_character_output out = {.worlds = w, .world_count = m->node_count};
    if (!size || sinew_character_init(memory, size, &d, &c, &e) || sinew_character_play(c, 1, 0.5f, true, &e))
        return fprintf(stderr, "%s\n", e.message), 3; /* above: into clip 1 over half a second, in step */
    float *p = w[ik.end].m + 12, *s = w[m->node_parents[m->node_parents[ik.end]]].m + 12, miss = 0;
    for (int frame = 0; frame < 45 && !sinew_character_advance(c, 1.0f / 60, &e); frame++) {
        sinew_character_set_target(c, 0, ik.target, 0.0f, &e); /* the clips' pose, then the joint on target */
        sinew_character_evaluate(c, &out, &e);
        for (int k = 0; k < 3; k++)
            ik.target[k] = p[k] + (s[k] - p[k]) / 4;
        if (sinew_character_set_target(c, 0, ik.target, 1.0f, &e) || sinew_character_evaluate(c, &out, &e))
            return fprintf(stderr, "%s\n", e.message), 4;
        miss = fmaxf(miss, fabsf(p[0] - ik.target[0]) + fabsf(p[1] - ik.target[1]) + fabsf(p[2] - ik.target[2]));
    }
    printf("%s: %s at %.2f of clip 1, off its target by %.1e\n", m->source, argv[2], sinew_character_weight(c, 1),
           miss);
    free(memory), free(w), sinew_clip_layout_free(clips[0]), sinew_clip_layout_free(clips[1]), sinew_model_free(m);
    return miss < 1e-3f ? 0 : 1;
}
