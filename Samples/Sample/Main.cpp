// nrd-sample: runs a method on a scene-lab scene, writes noisy / denoised / truth images, a
// side-by-side strip, a metrics table and a JSON report.
//
// nrd-sample --scene NAME|FILE.json --method METHOD|NONE [--frames N] [--size WxH] [--truth-spp K]
//            [--seed S] [--warmup W] [--device I] [--settings FILE.json] [--out DIR] [--json FILE]
//            [--signal shadow|diffuse|specular|diffuse_occlusion|specular_occlusion] [--validation]
//            [--cache DIR|none] [--bounds] [--confidence] [--quiet]
// --confidence: CONFIDENCE runs first on the lab's temporal gradients and feeds the method's
// IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE (REBLUR_* but the occlusion variants, RELAX_*; settings
// under "confidence").
#include "ImageIO.h"
#include "MethodRunner.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace
{

void PrintUsage()
{
    std::fprintf(stderr,
                 "usage: nrd-sample --scene NAME|FILE.json --method METHOD|NONE [--frames N] [--size WxH]\n"
                 "                  [--truth-spp K] [--seed S] [--warmup W] [--device I] [--settings FILE.json]\n"
                 "                  [--out DIR] [--json FILE] [--validation] [--cache DIR|none] [--bounds] [--confidence] [--quiet]\n"
                 "                  [--signal shadow|diffuse|specular|diffuse_occlusion|specular_occlusion]\n");
}

bool ParseUint(const char* s, uint32_t& out)
{
    char* end = nullptr;
    unsigned long v = std::strtoul(s, &end, 10);
    if (!s[0] || *end || v > 0xFFFFFFFFul)
        return false;
    out = uint32_t(v);
    return true;
}

} // namespace

int main(int argc, char** argv)
{
    nrdlab::RunOptions o;
    std::string outDir = "out", jsonPath;
    bool quiet = false;
    for (int i = 1; i < argc; i++)
    {
        std::string a = argv[i];
        auto value = [&](const char*& v) {
            if (i + 1 >= argc)
            {
                std::fprintf(stderr, "error: %s needs a value\n", a.c_str());
                return false;
            }
            v = argv[++i];
            return true;
        };
        const char* v = nullptr;
        bool ok = true;
        if (a == "--help" || a == "-h")
        {
            PrintUsage();
            return 0;
        }
        else if (a == "--validation")
            o.validation = true;
        else if (a == "--quiet")
            quiet = true;
        else if (a == "--bounds")
            o.bounds = true;
        else if (a == "--confidence")
            o.confidence = true;
        else if (!value(v))
            return 2;
        else if (a == "--scene")
            o.scene = v;
        else if (a == "--method")
            o.method = v;
        else if (a == "--signal")
            o.signal = v;
        else if (a == "--frames")
            ok = ParseUint(v, o.frames) && o.frames > 0;
        else if (a == "--truth-spp")
            ok = ParseUint(v, o.truthSpp) && o.truthSpp > 0;
        else if (a == "--seed")
            ok = ParseUint(v, o.seed);
        else if (a == "--warmup")
            ok = ParseUint(v, o.warmup);
        else if (a == "--device")
        {
            uint32_t d = 0;
            ok = ParseUint(v, d);
            o.device = int32_t(d);
        }
        else if (a == "--size")
            ok = std::sscanf(v, "%ux%u", &o.width, &o.height) == 2;
        else if (a == "--settings")
        {
            std::ifstream f(v);
            std::stringstream ss;
            ss << f.rdbuf();
            ok = bool(f);
            o.settingsJson = ss.str();
        }
        else if (a == "--out")
            outDir = v;
        else if (a == "--json")
            jsonPath = v;
        else if (a == "--cache")
            o.cacheDirectory = v;
        else
        {
            std::fprintf(stderr, "error: unknown option %s\n", a.c_str());
            PrintUsage();
            return 2;
        }
        if (!ok)
        {
            std::fprintf(stderr, "error: bad value '%s' for %s\n", v, a.c_str());
            return 2;
        }
    }

    auto start = std::chrono::steady_clock::now();
    o.progress = [&](uint32_t frame, uint32_t frames) {
        if (quiet)
            return;
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::fprintf(stderr, "\r[%s %s] frame %u/%u  %.1f s", o.scene.c_str(), o.method.c_str(), frame + 1, frames, s);
        std::fflush(stderr);
    };

    nrdlab::RunReport r;
    std::string error;
    bool ok = nrdlab::RunMethod(o, r, error);
    if (!quiet)
        std::fprintf(stderr, "\n");
    if (!ok)
    {
        std::fprintf(stderr, "error: %s\n", error.c_str());
        return 1;
    }

    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    std::string base = outDir + "/" + r.scene + "_" + r.method + "_" + r.signal;
    bool written = true;
    std::string ioError;
    // Shadows and occlusion are already in [0, 1]: no tone mapping, and stored linearly so values read
    // as they are.
    nrdlab::PngOptions png;
    png.toneMap = r.signal == "diffuse" || r.signal == "specular";
    png.srgb = png.toneMap;
    for (auto& [suffix, image] : {std::pair<const char*, const nrdlab::Image*>{"noisy", &r.noisy},
                                  {"denoised", &r.denoised}, {"truth", &r.truth}})
    {
        written &= nrdlab::WritePng(base + "_" + suffix + ".png", *image, &ioError, png);
        written &= nrdlab::WriteExr(base + "_" + suffix + ".exr", *image, &ioError);
    }
    written &= nrdlab::WriteSideBySide(base + "_strip.png", {r.noisy, r.denoised, r.truth}, &ioError, 4, png);
    if (jsonPath.empty())
        jsonPath = base + ".json";
    std::ofstream json(jsonPath);
    json << nrdlab::ReportToJson(r) << "\n";
    written &= bool(json);
    if (!written)
    {
        std::fprintf(stderr, "error: writing results: %s\n", ioError.c_str());
        return 1;
    }

    const nrdlab::FrameMetrics& m = r.mean;
    std::printf("scene %s, method %s, signal %s, %ux%u, %u frames (warm-up %u), truth %u spp, device %s\n",
                r.scene.c_str(), r.method.c_str(), r.signal.c_str(), r.width, r.height, r.frames, r.warmup, r.truthSpp,
                r.device.c_str());
    std::printf("%-24s %12s %12s\n", "metric", "noisy", "denoised");
    std::printf("%-24s %12.5f %12.5f\n", "relMSE", m.relmseNoisy, m.relmseDenoised);
    std::printf("%-24s %12.3f %12.3f\n", "PSNR (dB)", m.psnrNoisy, m.psnrDenoised);
    std::printf("%-24s %12.4f %12.4f\n", "SSIM", m.ssimNoisy, m.ssimDenoised);
    std::printf("%-24s %12.4f %12.4f\n", "FLIP", m.flipNoisy, m.flipDenoised);
    std::printf("%-24s %12.5f %12.5f   (truth %.5f)\n", "temporal instability", m.temporalInstabilityNoisy,
                m.temporalInstabilityDenoised, m.temporalInstabilityTruth);
    std::printf("%-24s %12s %12d   (event frame %d)\n", "lag (frames)", "", r.lagFrames, r.lagEventFrame);
    std::printf("%-24s %12s %12d   (event frame %d; relMSE of %ux%u block means %.5f)\n", "lag, low-pass (frames)", "",
                r.lagLowpassFrames, r.lagLowpassEventFrame, nrdlab::kLowpassBlock, nrdlab::kLowpassBlock,
                m.relmseLowpassDenoised);
    if (o.bounds)
    {
        std::printf("reuse bounds: reprojected truth relMSE %.5f; oracle relMSE %.5f, temporal instability %.5f\n",
                    m.boundReprojectedTruth, m.boundOracle, m.boundOracleInstability);
        std::printf("reuse bounds: oracle relMSE by blend factor:");
        for (int k = 0; k < 3; k++)
            std::printf(" %.2f: %.5f", double(nrdlab::kBoundAlphas[k]), m.boundOracleByAlpha[k]);
        std::printf("\n");
    }
    std::printf("GPU %.3f ms/frame, %u dispatches, %u pipelines, %.2f MiB device memory\n", r.gpuMsPerFrame,
                r.dispatchesPerFrame, r.pipelines, double(r.memoryBytes) / (1024.0 * 1024.0));
    for (const auto& p : r.passMs)
        std::printf("  %-40s %8.3f ms\n", p.first.c_str(), p.second);
    std::printf("scene lab: %.1f ms/frame noisy, %.1f ms/frame truth (after the warm-up)\n", r.renderNoisyMs,
                r.renderTruthMs);
    for (const nrdlab::RunReport::MeshInfo& mesh : r.meshes)
        std::printf("mesh %s: %u triangles, BVH of %u nodes (depth %u) built in %.1f ms\n", mesh.file.c_str(),
                    mesh.triangles, mesh.bvhNodes, mesh.bvhDepth, mesh.bvhBuildMs);
    if (r.raysFullRate > 0.0)
        std::printf("rays traced: %.0f per frame of %.0f at full rate (%.1f%%, %.1f%% saved)\n", r.raysTraced,
                    r.raysFullRate, 100.0 * r.rayRatio, 100.0 * (1.0 - r.rayRatio));
    std::printf("images: %s_{noisy,denoised,truth}.{png,exr}, %s_strip.png; report: %s\n", base.c_str(), base.c_str(),
                jsonPath.c_str());
    return 0;
}
