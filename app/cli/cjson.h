/* cJSON for the command line's --json output, loaded when the first JSON value is made: the
 * program does not link libcjson, so that a command that prints no JSON (`sinew --help`, `sinew
 * info FILE`) never loads it (0.06 ms of every start here, a library mapped and relocated).
 *
 * Include this instead of <cjson/cJSON.h>. The functions below keep their names (each is a macro
 * for the pointer loaded); the first use loads the library, and a program that cannot load it
 * stops with a message and EXIT_UNAVAILABLE. A function not listed here is refused by the linker. */
#ifndef SINEW_CLI_CJSON_H
#define SINEW_CLI_CJSON_H

#include <stdbool.h>

#include <cjson/cJSON.h>

#define CLI_CJSON_FUNCTIONS(X)                                                                                         \
    X(cJSON_AddArrayToObject)                                                                                          \
    X(cJSON_AddBoolToObject)                                                                                           \
    X(cJSON_AddItemToArray)                                                                                            \
    X(cJSON_AddItemToObject)                                                                                           \
    X(cJSON_AddNullToObject)                                                                                           \
    X(cJSON_AddNumberToObject)                                                                                         \
    X(cJSON_AddObjectToObject)                                                                                         \
    X(cJSON_AddStringToObject)                                                                                         \
    X(cJSON_CreateArray)                                                                                               \
    X(cJSON_CreateBool)                                                                                                \
    X(cJSON_CreateNull)                                                                                                \
    X(cJSON_CreateNumber)                                                                                              \
    X(cJSON_CreateObject)                                                                                              \
    X(cJSON_CreateString)                                                                                              \
    X(cJSON_Delete)                                                                                                    \
    X(cJSON_Print)                                                                                                     \
    X(cJSON_PrintUnformatted)

#define CLI_CJSON_ONE(name) +1
enum { CLI_CJSON_SYMBOLS = 0 CLI_CJSON_FUNCTIONS(CLI_CJSON_ONE) };
#undef CLI_CJSON_ONE
typedef union cli_cjson_api {
    struct {
#define CLI_CJSON_MEMBER(name) __typeof__(name) *name;
        CLI_CJSON_FUNCTIONS(CLI_CJSON_MEMBER)
#undef CLI_CJSON_MEMBER
    };
    void *symbol[CLI_CJSON_SYMBOLS];
} cli_cjson_api;

/* The functions, the library loaded at the first call (thread-safe); exits the program with a
 * message when it cannot be. */
const cli_cjson_api *cli_cjson(void);

/* Prints `value` on standard output (indented, or on one line), then deletes it. */
void cli_json_print(cJSON *value, bool indented);

#define cJSON_AddArrayToObject (cli_cjson()->cJSON_AddArrayToObject)
#define cJSON_AddBoolToObject (cli_cjson()->cJSON_AddBoolToObject)
#define cJSON_AddItemToArray (cli_cjson()->cJSON_AddItemToArray)
#define cJSON_AddItemToObject (cli_cjson()->cJSON_AddItemToObject)
#define cJSON_AddNullToObject (cli_cjson()->cJSON_AddNullToObject)
#define cJSON_AddNumberToObject (cli_cjson()->cJSON_AddNumberToObject)
#define cJSON_AddObjectToObject (cli_cjson()->cJSON_AddObjectToObject)
#define cJSON_AddStringToObject (cli_cjson()->cJSON_AddStringToObject)
#define cJSON_CreateArray (cli_cjson()->cJSON_CreateArray)
#define cJSON_CreateBool (cli_cjson()->cJSON_CreateBool)
#define cJSON_CreateNull (cli_cjson()->cJSON_CreateNull)
#define cJSON_CreateNumber (cli_cjson()->cJSON_CreateNumber)
#define cJSON_CreateObject (cli_cjson()->cJSON_CreateObject)
#define cJSON_CreateString (cli_cjson()->cJSON_CreateString)
#define cJSON_Delete (cli_cjson()->cJSON_Delete)
#define cJSON_Print (cli_cjson()->cJSON_Print)
#define cJSON_PrintUnformatted (cli_cjson()->cJSON_PrintUnformatted)

#endif
