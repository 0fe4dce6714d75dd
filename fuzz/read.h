/* Shared by the importer fuzz targets (fuzz_fbx, fuzz_gltf, fuzz_collada, fuzz_iqm): any bytes either
 * read (and then build into a runtime model that is exercised like a player would) or are
 * refused with a message that names the file; never a crash, a hang or a sanitizer report. */
#ifndef SINEW_FUZZ_READ_H
#define SINEW_FUZZ_READ_H

#include <stddef.h>
#include <stdint.h>

#include "import/internal.h"

typedef sinew_result (*fuzz_reader)(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                    sinew_error *error);

/* Reads `data` as the file `name` with `reader`; aborts on anything but a clean result. */
int fuzz_read(fuzz_reader reader, const char *name, const uint8_t *data, size_t size);

#endif
