// Hit distance normalization parameters shared by the radiance + hit distance methods.
#include "InstanceImpl.h"

#include <cmath>

namespace nrd
{

Result ValidateHitDistanceParameters(const HitDistanceParameters& p, const char* owner, const Logger& log)
{
    struct Field
    {
        const char* name;
        float value;
        bool valid;
        const char* range;
    };
    const Field fields[] = {
        {"A", p.A, p.A > 0.0f, "> 0"},
        {"B", p.B, p.B >= 0.0f, ">= 0"},
        {"C", p.C, p.C >= 1.0f, ">= 1"},
        {"D", p.D, p.D <= 0.0f, "<= 0"},
    };
    for (const Field& f : fields)
    {
        if (!std::isfinite(f.value) || !f.valid)
        {
            log.Error("SetMethodSettings: %s::%s %g must be finite and %s", owner, f.name, double(f.value), f.range);
            return Result::INVALID_ARGUMENT;
        }
    }
    return Result::SUCCESS;
}

} // namespace nrd
