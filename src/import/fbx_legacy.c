/* FBX 5.x and 6.x documents indexed into the scene of fbx_scene.h. */
#include "fbx_scene.h"

sinew_result fbx_legacy_index(scene *s)
{
    return sinew_fail(s->error, SINEW_ERROR_FORMAT, "%s: FBX %u.%u is not read yet", s->path, s->doc.version / 1000,
                      s->doc.version % 1000 / 100);
}
