// Evaluates Shaders/Include/LightingChange.glsl on a list of cases, for LightingChangeTests.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LightingChange.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// Per case, 4 floats: record, isChanged (0 / 1), a value to pack with the record, a channel to unpack.
layout(set = 0, binding = 0, std430) readonly buffer Cases { float gCases[]; };
// Per case, 8 floats: the updated record, whether it is moving, whether the given record is moving,
// the packed channel (given record and value), its record and value unpacked, the given channel's
// record and value unpacked.
layout(set = 0, binding = 1, std430) buffer Results { float gResults[]; };
layout(push_constant) uniform Push { uint gCaseNum; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= gCaseNum)
        return;
    uint c = i * 4u;
    uint record = uint(gCases[c + 0u]);
    bool isChanged = gCases[c + 1u] != 0.0;
    float value = gCases[c + 2u];
    float channel = gCases[c + 3u];

    uint updated = _NRD_LightingChange_Update(record, isChanged);
    float packed = _NRD_LightingChange_Pack(record, value);

    uint r = i * 8u;
    gResults[r + 0u] = float(updated);
    gResults[r + 1u] = _NRD_LightingChange_IsMoving(updated) ? 1.0 : 0.0;
    gResults[r + 2u] = _NRD_LightingChange_IsMoving(record) ? 1.0 : 0.0;
    gResults[r + 3u] = packed;
    gResults[r + 4u] = float(_NRD_LightingChange_UnpackRecord(packed));
    gResults[r + 5u] = _NRD_LightingChange_UnpackValue(packed);
    gResults[r + 6u] = float(_NRD_LightingChange_UnpackRecord(channel));
    gResults[r + 7u] = _NRD_LightingChange_UnpackValue(channel);
}
