/* Loading libxml2 on first use (xml.h). */
#include <pthread.h>
#include <stdio.h>

#include "../core/internal.h"
#include "xml.h"

#ifndef SINEW_LIBXML2_SONAME
#error "the build names libxml2's soname (CMakeLists.txt: SINEW_LIBXML2_SONAME)"
#endif

const import_xml_api *import_xml;

static import_xml_api loaded;
static char failure[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void load(void)
{
#define IMPORT_XML_NAME(name) #name,
    static const char *const names[IMPORT_XML_SYMBOLS] = {IMPORT_XML_FUNCTIONS(IMPORT_XML_NAME) "xmlFree"};
#undef IMPORT_XML_NAME
    if (sinew_lazy_open(SINEW_LIBXML2_SONAME, names, loaded.symbol, IMPORT_XML_SYMBOLS, failure, sizeof failure))
        import_xml = &loaded;
}

bool import_xml_load(char *why, size_t size)
{
    pthread_once(&once, load);
    if (!import_xml && why && size)
        snprintf(why, size, "%s", failure);
    return import_xml != NULL;
}
