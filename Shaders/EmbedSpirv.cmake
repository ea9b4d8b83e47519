# cmake -DIN=<file.spv> -DOUT=<file.cpp> -DNAME=<name> -P EmbedSpirv.cmake
file(READ ${IN} hex HEX)
string(LENGTH "${hex}" len)
math(EXPR words "${len} / 8")
# SPIR-V is little-endian words: reorder each 4-byte group into a 0x######## literal.
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u," body "${hex}")
string(REGEX REPLACE "((0x[0-9a-f]+u,){8})" "\\1\n    " body "${body}")
file(WRITE ${OUT} "// Generated from ${NAME}.spv by Shaders/EmbedSpirv.cmake.
#include <cstdint>

namespace nrd
{
extern const uint32_t g_${NAME}[];
extern const uint32_t g_${NAME}_size;
const uint32_t g_${NAME}[] = {
    ${body}
};
const uint32_t g_${NAME}_size = ${words}u * 4u;
} // namespace nrd
")
