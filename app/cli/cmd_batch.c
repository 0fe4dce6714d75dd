/* `sinew batch`: whole motion libraries to arrays on a Dask cluster. The work is the Python
 * package's (python/sinew/batch.py, over libsinew through cffi); this runs it with Debian's
 * python3, the package and the library found beside this program (build tree or install). */
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

static bool is_file(const char *path)
{
    return access(path, R_OK) == 0;
}

/* The folder of the running program, without a trailing slash. */
static bool program_folder(char *out, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", out, size - 1);
    if (n <= 0)
        return false;
    out[n] = '\0';
    char *slash = strrchr(out, '/');
    if (!slash)
        return false;
    *slash = '\0';
    return true;
}

/* The folder holding the sinew Python package: $SINEW_PYTHON_DIR, the installed share/sinew/python
 * beside the program, or the source tree this program was built from. */
static bool python_folder(const char *bin, char *out, size_t size)
{
    const char *given = getenv("SINEW_PYTHON_DIR");
    const char *candidates[3];
    char installed[PATH_MAX + 64];
    snprintf(installed, sizeof installed, "%s/%s", bin, SINEW_BIN_TO_PYTHON);
    int n = 0;
    if (given && *given)
        candidates[n++] = given;
    candidates[n++] = installed;
    candidates[n++] = SINEW_SOURCE_PYTHON;
    for (int i = 0; i < n; i++) {
        char probe[PATH_MAX + 64];
        snprintf(probe, sizeof probe, "%s/sinew/batch.py", candidates[i]);
        if (is_file(probe)) {
            snprintf(out, size, "%s", candidates[i]);
            return true;
        }
    }
    return false;
}

/* libsinew for the package: a build tree's beside the program, or the installed one. */
static void library_for(const char *bin)
{
    if (getenv("SINEW_LIBRARY"))
        return;
    const char *names[] = {"%s/libsinew.so", "%s/" SINEW_BIN_TO_LIB "/libsinew.so." SINEW_SOVERSION};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[PATH_MAX + 64];
        snprintf(path, sizeof path, names[i], bin);
        if (is_file(path)) {
            setenv("SINEW_LIBRARY", path, 1);
            return;
        }
    }
}

int cmd_batch(int argc, char **argv)
{
    char bin[PATH_MAX], folder[PATH_MAX];
    if (!program_folder(bin, sizeof bin))
        snprintf(bin, sizeof bin, ".");
    if (!python_folder(bin, folder, sizeof folder)) {
        cli_error("batch: the sinew Python package is not installed (looked in $SINEW_PYTHON_DIR, %s/%s and %s)", bin,
                  SINEW_BIN_TO_PYTHON, SINEW_SOURCE_PYTHON);
        return EXIT_UNAVAILABLE;
    }
    const char *old = getenv("PYTHONPATH");
    char path[2 * PATH_MAX + 2];
    snprintf(path, sizeof path, "%s%s%s", folder, old && *old ? ":" : "", old && *old ? old : "");
    setenv("PYTHONPATH", path, 1);
    library_for(bin);
    /* Debian's python3 has python3-numpy, -cffi and -distributed; $SINEW_PYTHON names another */
    const char *python = getenv("SINEW_PYTHON");
    if (!python || !*python)
        python = is_file("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    char **args = calloc((size_t)argc + 5, sizeof *args);
    if (!args) {
        cli_error("batch: out of memory");
        return EXIT_UNAVAILABLE;
    }
    int n = 0;
    args[n++] = (char *)python;
    args[n++] = "-m";
    args[n++] = "sinew";
    args[n++] = "batch";
    for (int i = 1; i < argc; i++)
        args[n++] = argv[i];
    args[n] = NULL;
    fflush(NULL);
    execvp(python, args);
    cli_error("batch: cannot run %s (%s); `sinew batch` needs Python 3 with numpy, cffi and Dask distributed "
              "(scripts/deps.sh installs python3-numpy python3-cffi python3-distributed)",
              python, strerror(errno));
    free(args);
    return EXIT_UNAVAILABLE;
}
