/* sinew/sinew.h — everything in libsinew: the runtime model, evaluation and import.
 * A runtime user that only poses and skins needs sinew/model.h and sinew/anim.h
 * (library sinew_core); sinew/import.h needs sinew_import, which links Assimp;
 * sinew/render.h, camera.h and headless.h need sinew_render (libepoxy, EGL). */
#ifndef SINEW_SINEW_H
#define SINEW_SINEW_H

#include "sinew/anim.h"
#include "sinew/arm.h"
#include "sinew/camera.h"
#include "sinew/headless.h"
#include "sinew/import.h"
#include "sinew/model.h"
#include "sinew/muscle.h"
#include "sinew/muscle_file.h"
#include "sinew/muscle_rig.h"
#include "sinew/render.h"
#include "sinew/result.h"

#define SINEW_VERSION_STRING "0.1.0"

#endif
