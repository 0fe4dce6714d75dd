/* Loading cJSON on first use (cjson.h). */
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"
#include "cjson.h"

#ifndef SINEW_CJSON_SONAME
#error "the build names libcjson's soname (CMakeLists.txt: SINEW_CJSON_SONAME)"
#endif

static cli_cjson_api loaded;
static bool ready;

#define CLI_CJSON_NAME(name) #name,
static const char *const names[CLI_CJSON_SYMBOLS] = {CLI_CJSON_FUNCTIONS(CLI_CJSON_NAME)};
#undef CLI_CJSON_NAME

static pthread_once_t once = PTHREAD_ONCE_INIT;
static char failure[256];

static void load(void)
{
    void *handle = dlopen(SINEW_CJSON_SONAME, RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
        snprintf(failure, sizeof failure, "cannot load %s, which --json output needs: %s", SINEW_CJSON_SONAME,
                 dlerror());
        return;
    }
    for (int i = 0; i < CLI_CJSON_SYMBOLS; i++)
        if (!(loaded.symbol[i] = dlsym(handle, names[i]))) {
            snprintf(failure, sizeof failure, "%s, which --json output needs, lacks %s", SINEW_CJSON_SONAME, names[i]);
            return;
        }
    ready = true;
}

const cli_cjson_api *cli_cjson(void)
{
    pthread_once(&once, load);
    if (!ready) {
        cli_error("%s", failure);
        exit(EXIT_UNAVAILABLE);
    }
    return &loaded;
}

void cli_json_print(cJSON *value, bool indented)
{
    char *text = indented ? cJSON_Print(value) : cJSON_PrintUnformatted(value);
    if (text)
        puts(text);
    free(text);
    cJSON_Delete(value);
}
