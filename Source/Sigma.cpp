// SIGMA: replaced by the SIGMA implementation.
#include "InstanceImpl.h"

namespace nrd
{
std::unique_ptr<MethodBase> CreateSigma(MethodBuilder&, Method)
{
    return nullptr;
}
} // namespace nrd
