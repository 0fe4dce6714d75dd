/* Shared by the importer fuzz targets (fuzz_fbx, fuzz_gltf, fuzz_collada, fuzz_iqm): any bytes given
 * to the public sinew_import_memory() either import (and the model is exercised as a player would)
 * or are refused with a message that names the file; never a crash, a hang, a sanitizer report or
 * SINEW_ERROR_INTERNAL (a model built that does not read back). External parts are refused (the
 * read_file callback finds none), so nothing is read from the disk. */
#ifndef SINEW_FUZZ_READ_H
#define SINEW_FUZZ_READ_H

#include <stddef.h>
#include <stdint.h>

/* Imports `data` as `format` named `name`; aborts on anything but a clean result. */
int fuzz_read(const char *format, const char *name, const uint8_t *data, size_t size);

#endif
