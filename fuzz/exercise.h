/* Shared by the fuzz targets: exercises a loaded model; aborts when a step that must succeed
 * on any model that loaded fails. */
#ifndef SINEW_FUZZ_EXERCISE_H
#define SINEW_FUZZ_EXERCISE_H

#include "sinew/sinew.h"

void fuzz_exercise(const sinew_model *m);

#endif
