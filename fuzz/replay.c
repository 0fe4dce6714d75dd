/* Runs the fuzz target once on each file named (a regression run of the corpus without
 * libFuzzer, so that `make test` builds and checks the target with any compiler). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        FILE *f = fopen(argv[i], "rb");
        if (!f) {
            fprintf(stderr, "%s: cannot open\n", argv[i]);
            return 1;
        }
        size_t cap = 1 << 16, size = 0;
        uint8_t *data = malloc(cap);
        size_t n;
        while (data && (n = fread(data + size, 1, cap - size, f)) > 0) {
            size += n;
            if (size == cap) {
                uint8_t *grown = realloc(data, cap *= 2);
                if (!grown)
                    free(data);
                data = grown;
            }
        }
        fclose(f);
        if (!data)
            return 1;
        LLVMFuzzerTestOneInput(data, size);
        /* Every prefix too: the cheapest mutation, and the one a truncated download makes. */
        for (size_t k = 0; k < size; k += 1 + size / 512)
            LLVMFuzzerTestOneInput(data, k);
        free(data);
        printf("%s: %zu bytes ok\n", argv[i], size);
    }
    return 0;
}
