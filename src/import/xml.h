/* libxml2, loaded when a file first needs it (COLLADA, an FBX's XML vertex cache, writing
 * COLLADA): neither sinew nor libsinew links it, so that a program that never reads XML never
 * loads it, nor the ICU and C++ libraries it pulls in (about 4 ms of every process start).
 *
 * Include this instead of libxml2's headers. Call import_xml_load() before the first libxml2
 * call of an entry point; after it succeeds, the libxml2 functions below are called by their
 * own names (each name is a macro for the pointer loaded). A function not listed here is
 * refused by the linker. */
#ifndef SINEW_IMPORT_XML_H
#define SINEW_IMPORT_XML_H

#include <stdbool.h>
#include <stddef.h>

#include <libxml/hash.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlwriter.h>

#define IMPORT_XML_FUNCTIONS(X)                                                                                        \
    X(xmlBufferContent)                                                                                                \
    X(xmlBufferCreate)                                                                                                 \
    X(xmlBufferFree)                                                                                                   \
    X(xmlBufferLength)                                                                                                 \
    X(xmlDocGetRootElement)                                                                                            \
    X(xmlFreeDoc)                                                                                                      \
    X(xmlFreeTextWriter)                                                                                               \
    X(xmlGetLineNo)                                                                                                    \
    X(xmlGetProp)                                                                                                      \
    X(xmlHashAddEntry)                                                                                                 \
    X(xmlHashCreate)                                                                                                   \
    X(xmlHashFree)                                                                                                     \
    X(xmlHashLookup)                                                                                                   \
    X(xmlNewTextWriterMemory)                                                                                          \
    X(xmlNodeGetContent)                                                                                               \
    X(xmlReadMemory)                                                                                                   \
    X(xmlSetGenericErrorFunc)                                                                                          \
    X(xmlSetStructuredErrorFunc)                                                                                       \
    X(xmlStrEqual)                                                                                                     \
    X(xmlStrdup)                                                                                                       \
    X(xmlStrndup)                                                                                                      \
    X(xmlTextWriterEndDocument)                                                                                        \
    X(xmlTextWriterEndElement)                                                                                         \
    X(xmlTextWriterSetIndent)                                                                                          \
    X(xmlTextWriterSetIndentString)                                                                                    \
    X(xmlTextWriterStartDocument)                                                                                      \
    X(xmlTextWriterStartElement)                                                                                       \
    X(xmlTextWriterWriteAttribute)                                                                                     \
    X(xmlTextWriterWriteElement)                                                                                       \
    X(xmlTextWriterWriteString)                                                                                        \
    X(__xmlGenericError)                                                                                               \
    X(__xmlGenericErrorContext)                                                                                        \
    X(__xmlStructuredError)                                                                                            \
    X(__xmlStructuredErrorContext)

#define IMPORT_XML_ONE(name) +1
enum { IMPORT_XML_SYMBOLS = 1 IMPORT_XML_FUNCTIONS(IMPORT_XML_ONE) };
#undef IMPORT_XML_ONE
typedef union import_xml_api {
    struct {
#define IMPORT_XML_MEMBER(name) __typeof__(name) *name;
        IMPORT_XML_FUNCTIONS(IMPORT_XML_MEMBER)
#undef IMPORT_XML_MEMBER
        xmlFreeFunc *xmlFree; /* a variable of libxml2's (its free) */
    };
    void *symbol[IMPORT_XML_SYMBOLS];
} import_xml_api;

/* The loaded functions: valid once import_xml_load() has succeeded. */
extern const import_xml_api *const import_xml;

/* Loads libxml2 once (thread-safe); false with the reason in `why` (the library named, dlerror()'s
 * words) when it cannot be. */
bool import_xml_load(char *why, size_t size);

#define xmlBufferContent (import_xml->xmlBufferContent)
#define xmlBufferCreate (import_xml->xmlBufferCreate)
#define xmlBufferFree (import_xml->xmlBufferFree)
#define xmlBufferLength (import_xml->xmlBufferLength)
#define xmlDocGetRootElement (import_xml->xmlDocGetRootElement)
#define xmlFreeDoc (import_xml->xmlFreeDoc)
#define xmlFreeTextWriter (import_xml->xmlFreeTextWriter)
#define xmlGetLineNo (import_xml->xmlGetLineNo)
#define xmlGetProp (import_xml->xmlGetProp)
#define xmlHashAddEntry (import_xml->xmlHashAddEntry)
#define xmlHashCreate (import_xml->xmlHashCreate)
#define xmlHashFree (import_xml->xmlHashFree)
#define xmlHashLookup (import_xml->xmlHashLookup)
#define xmlNewTextWriterMemory (import_xml->xmlNewTextWriterMemory)
#define xmlNodeGetContent (import_xml->xmlNodeGetContent)
#define xmlReadMemory (import_xml->xmlReadMemory)
#define xmlSetGenericErrorFunc (import_xml->xmlSetGenericErrorFunc)
#define xmlSetStructuredErrorFunc (import_xml->xmlSetStructuredErrorFunc)
#define xmlStrEqual (import_xml->xmlStrEqual)
#define xmlStrdup (import_xml->xmlStrdup)
#define xmlStrndup (import_xml->xmlStrndup)
#define xmlTextWriterEndDocument (import_xml->xmlTextWriterEndDocument)
#define xmlTextWriterEndElement (import_xml->xmlTextWriterEndElement)
#define xmlTextWriterSetIndent (import_xml->xmlTextWriterSetIndent)
#define xmlTextWriterSetIndentString (import_xml->xmlTextWriterSetIndentString)
#define xmlTextWriterStartDocument (import_xml->xmlTextWriterStartDocument)
#define xmlTextWriterStartElement (import_xml->xmlTextWriterStartElement)
#define xmlTextWriterWriteAttribute (import_xml->xmlTextWriterWriteAttribute)
#define xmlTextWriterWriteElement (import_xml->xmlTextWriterWriteElement)
#define xmlTextWriterWriteString (import_xml->xmlTextWriterWriteString)
/* libxml2's per-thread globals are macros over these functions */
#define __xmlGenericError (import_xml->__xmlGenericError)
#define __xmlGenericErrorContext (import_xml->__xmlGenericErrorContext)
#define __xmlStructuredError (import_xml->__xmlStructuredError)
#define __xmlStructuredErrorContext (import_xml->__xmlStructuredErrorContext)
#undef xmlFree
#define xmlFree (*import_xml->xmlFree)

#endif
