// Creates a denoiser with every method of the library and prints its description.
#include <NRD.h>
#if NRD_CONSUMER_HAS_INTEGRATION
#  include <NRDIntegration.h>
#endif

#include <cstdio>
#include <vector>

int main()
{
    const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
    std::printf("NRD %u.%u.%u, %u methods\n", lib.versionMajor, lib.versionMinor, lib.versionBuild, lib.supportedMethodsNum);

    std::vector<nrd::MethodDesc> methods;
    for (uint32_t i = 0; i < lib.supportedMethodsNum; i++)
        methods.push_back({i, lib.supportedMethods[i]});

    nrd::DenoiserCreationDesc desc;
    desc.methods = methods.data();
    desc.methodsNum = uint32_t(methods.size());
    desc.renderWidth = 1920;
    desc.renderHeight = 1080;
    nrd::Denoiser* denoiser = nullptr;
    if (nrd::CreateDenoiser(desc, denoiser) != nrd::Result::SUCCESS)
        return 1;
    const nrd::DenoiserDesc& d = nrd::GetDenoiserDesc(*denoiser);
    std::printf("pipelines %u, permanent textures %u, transient textures %u\n", d.pipelinesNum, d.permanentPoolSize,
                d.transientPoolSize);
    nrd::DestroyDenoiser(denoiser);
    return d.pipelinesNum > 0 ? 0 : 1;
}
