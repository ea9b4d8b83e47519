#include "SpirvReflect.h"

#include <map>

namespace nrdtest
{

namespace
{
enum : uint32_t
{
    OpName = 5,
    OpExecutionMode = 16,
    OpTypeInt = 21,
    OpTypeFloat = 22,
    OpTypeVector = 23,
    OpTypeMatrix = 24,
    OpTypeImage = 25,
    OpTypeSampler = 26,
    OpTypeSampledImage = 27,
    OpTypeRuntimeArray = 29,
    OpTypeStruct = 30,
    OpTypePointer = 32,
    OpVariable = 59,
    OpDecorate = 71,
    OpMemberDecorate = 72,

    DecorationBlock = 2,
    DecorationBufferBlock = 3,
    DecorationMatrixStride = 7,
    DecorationNonWritable = 24,
    DecorationBinding = 33,
    DecorationDescriptorSet = 34,
    DecorationOffset = 35,

    StorageUniformConstant = 0,
    StorageUniform = 2,
    StorageStorageBuffer = 12,

    ExecutionModeLocalSize = 17,
};

struct TypeInfo
{
    uint32_t op = 0;
    std::vector<uint32_t> operands;
};
} // namespace

bool ReflectSpirv(const uint32_t* words, size_t wordCount, SpirvModule& out, std::string& error)
{
    if (wordCount < 5 || words[0] != 0x07230203u)
    {
        error = "not a SPIR-V module";
        return false;
    }
    std::map<uint32_t, TypeInfo> types;
    std::map<uint32_t, std::string> names;
    std::map<uint32_t, uint32_t> sets, bindings, matrixStride;
    std::map<uint32_t, std::map<uint32_t, uint32_t>> memberOffsets;
    std::map<uint32_t, bool> isBlock, isBufferBlock, nonWritable;
    struct Variable
    {
        uint32_t id, pointerType, storage;
    };
    std::vector<Variable> variables;

    for (size_t i = 5; i < wordCount;)
    {
        uint32_t count = words[i] >> 16, op = words[i] & 0xFFFFu;
        if (count == 0 || i + count > wordCount)
        {
            error = "truncated instruction";
            return false;
        }
        const uint32_t* w = words + i;
        switch (op)
        {
        case OpName:
            names[w[1]] = reinterpret_cast<const char*>(w + 2);
            break;
        case OpExecutionMode:
            if (w[2] == ExecutionModeLocalSize && count >= 6)
            {
                out.localSize[0] = w[3];
                out.localSize[1] = w[4];
                out.localSize[2] = w[5];
            }
            break;
        case OpDecorate:
            if (w[2] == DecorationDescriptorSet)
                sets[w[1]] = w[3];
            else if (w[2] == DecorationBinding)
                bindings[w[1]] = w[3];
            else if (w[2] == DecorationBlock)
                isBlock[w[1]] = true;
            else if (w[2] == DecorationBufferBlock)
                isBufferBlock[w[1]] = true;
            else if (w[2] == DecorationNonWritable)
                nonWritable[w[1]] = true;
            break;
        case OpMemberDecorate:
            if (w[3] == DecorationOffset)
                memberOffsets[w[1]][w[2]] = w[4];
            else if (w[3] == DecorationNonWritable)
                nonWritable[w[1]] = true;
            else if (w[3] == DecorationMatrixStride)
                matrixStride[w[1]] = w[4];
            break;
        case OpVariable:
            variables.push_back({w[2], w[1], w[3]});
            break;
        default:
            if (op >= OpTypeInt && op <= OpTypePointer)
            {
                TypeInfo t;
                t.op = op;
                t.operands.assign(w + 2, w + count);
                types[w[1]] = t;
            }
            break;
        }
        i += count;
    }

    // Size of a type in a std140 block (scalars, vectors, matrices, nested structs).
    std::map<uint32_t, uint32_t> sizeCache;
    auto sizeOf = [&](auto& self, uint32_t typeId, uint32_t stride) -> uint32_t {
        const TypeInfo& t = types[typeId];
        switch (t.op)
        {
        case OpTypeInt:
        case OpTypeFloat:
            return t.operands[0] / 8;
        case OpTypeVector:
            return self(self, t.operands[0], 0) * t.operands[1];
        case OpTypeMatrix:
            return (stride ? stride : 16) * t.operands[1];
        case OpTypeStruct: {
            uint32_t end = 0;
            for (uint32_t m = 0; m < t.operands.size(); m++)
            {
                uint32_t offset = memberOffsets[typeId][m];
                uint32_t size = self(self, t.operands[m], matrixStride[typeId]);
                end = offset + size > end ? offset + size : end;
            }
            return end;
        }
        default:
            return 0;
        }
    };

    for (const Variable& v : variables)
    {
        if (v.storage != StorageUniformConstant && v.storage != StorageUniform && v.storage != StorageStorageBuffer)
            continue;
        const TypeInfo& pointer = types[v.pointerType];
        if (pointer.op != OpTypePointer)
            continue;
        uint32_t pointee = pointer.operands[1];
        const TypeInfo& t = types[pointee];
        SpirvBinding b;
        b.set = sets[v.id];
        b.binding = bindings[v.id];
        b.name = names[v.id];
        if (t.op == OpTypeImage)
            b.type = t.operands[5] == 2 ? SpirvDescriptor::STORAGE_IMAGE : SpirvDescriptor::SAMPLED_IMAGE;
        else if (t.op == OpTypeSampler)
            b.type = SpirvDescriptor::SAMPLER;
        else if (t.op == OpTypeStruct)
        {
            bool storage = v.storage == StorageStorageBuffer || isBufferBlock[pointee];
            if (storage)
                b.type = nonWritable[pointee] ? SpirvDescriptor::READONLY_STORAGE_BUFFER : SpirvDescriptor::STORAGE_BUFFER;
            else
            {
                b.type = SpirvDescriptor::UNIFORM_BUFFER;
                uint32_t size = sizeOf(sizeOf, pointee, 0);
                b.blockSize = (size + 15) / 16 * 16;
            }
            if (b.name.empty())
                b.name = names[pointee];
        }
        out.bindings.push_back(b);
    }
    return true;
}

} // namespace nrdtest
