/* A libcjson.so.1 without cJSON's functions (tests/CMakeLists.txt): what `sinew` meets where the
 * library it loads for --json output is not the one it needs. */
int sinew_test_not_cjson;
