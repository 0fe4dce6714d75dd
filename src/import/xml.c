/* Loading libxml2 on first use (xml.h). */
#include "../core/internal.h"
#include "xml.h"

#ifndef SINEW_LIBXML2_SONAME
#error "the build names libxml2's soname (CMakeLists.txt: SINEW_LIBXML2_SONAME)"
#endif

static import_xml_api loaded;
const import_xml_api *const import_xml = &loaded;
#define IMPORT_XML_NAME(name) #name,
static const char *const names[IMPORT_XML_SYMBOLS] = {IMPORT_XML_FUNCTIONS(IMPORT_XML_NAME) "xmlFree"};
#undef IMPORT_XML_NAME
static sinew_lazy_library libxml2 = {
    .soname = SINEW_LIBXML2_SONAME, .names = names, .symbols = loaded.symbol, .count = IMPORT_XML_SYMBOLS};

bool import_xml_load(char *why, size_t size)
{
    return sinew_lazy_load(&libxml2, why, size);
}
