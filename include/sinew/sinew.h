/* sinew/sinew.h — everything in libsinew: the runtime model, evaluation, import, rendering.
 * Start at sinew/character.h: a character's pose composed in one call. Installed, libsinew
 * (sinew::sinew, pkg-config sinew) holds all of it. A runtime user that only poses, skins and
 * solves muscles needs sinew/model.h, anim.h, blend.h, character.h, jobs.h, muscle.h,
 * muscle_rig.h and camera.h: libsinew_core (sinew::core, pkg-config sinew-core), libc and cglm
 * alone. */
#ifndef SINEW_SINEW_H
#define SINEW_SINEW_H

#include "sinew/anim.h"
#include "sinew/arm.h"
#include "sinew/arrays.h"
#include "sinew/blend.h"
#include "sinew/camera.h"
#include "sinew/character.h"
#include "sinew/headless.h"
#include "sinew/import.h"
#include "sinew/jobs.h"
#include "sinew/model.h"
#include "sinew/morph.h"
#include "sinew/muscle.h"
#include "sinew/muscle_file.h"
#include "sinew/muscle_rig.h"
#include "sinew/render.h"
#include "sinew/snapshot.h"
#include "sinew/result.h"
#include "sinew/version.h"

#endif
