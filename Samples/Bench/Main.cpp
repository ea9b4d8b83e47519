// nrd-bench: the speed-for-accuracy trade of every method the library lists, at every setting of
// its presets (Presets.json): GPU time per frame and per dispatch on fixed inputs, memory, the
// bandwidth bound, and the error against the scene lab's truth at an affordable size.
//
// nrd-bench [--methods A,B] [--sizes WxH,...] [--error-size WxH|none] [--error-jobs N]
//           [--scene NAME|FILE.json] [--frames N] [--truth-spp K] [--timed-frames N] [--warmup-frames N]
//           [--warmup-ms MS] [--frames-per-submission N] [--isolated-idle-ms MS] [--copy-mib N] [--budget-ms X]
//           [--presets FILE.json] [--out DIR] [--device I] [--cache DIR|none] [--deadline-s S] [--quiet]
// nrd-bench --validate REPORT.json
// nrd-bench --list-methods
#include "Bench.h"
#include "MethodRunner.h"
#include "NRD.h"
#include "VulkanContext.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

namespace
{

void PrintUsage()
{
    std::fprintf(stderr,
                 "usage: nrd-bench [--methods A,B] [--sizes WxH,...] [--error-size WxH|none] [--error-jobs N]\n"
                 "                 [--scene NAME|FILE.json] [--frames N] [--truth-spp K] [--timed-frames N]\n"
                 "                 [--warmup-frames N] [--warmup-ms MS] [--frames-per-submission N]\n"
                 "                 [--isolated-idle-ms MS] [--copy-mib N] [--budget-ms X]\n"
                 "                 [--presets FILE.json] [--out DIR] [--device I] [--cache DIR|none] [--deadline-s S]\n"
                 "                 [--quiet]\n"
                 "       nrd-bench --validate REPORT.json\n"
                 "       nrd-bench --list-methods\n");
}

bool ParseUint(const std::string& s, uint32_t& out)
{
    char* end = nullptr;
    unsigned long v = std::strtoul(s.c_str(), &end, 10);
    if (s.empty() || *end || v > 0xFFFFFFFFul)
        return false;
    out = uint32_t(v);
    return true;
}

bool ParseSize(const std::string& s, uint32_t& w, uint32_t& h)
{
    size_t x = s.find('x');
    return x != std::string::npos && ParseUint(s.substr(0, x), w) && ParseUint(s.substr(x + 1), h) && w && h &&
           w <= 8192 && h <= 8192;
}

std::vector<std::string> Split(const std::string& s)
{
    std::vector<std::string> parts;
    std::stringstream ss(s);
    std::string part;
    while (std::getline(ss, part, ','))
        if (!part.empty())
            parts.push_back(part);
    return parts;
}

bool ReadFile(const std::string& path, std::string& out)
{
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    out = ss.str();
    return bool(f);
}

// GB/s of probe copies (bytes read + written over the median time).
double Bandwidth(uint64_t bytes, const std::vector<double>& ms)
{
    double median = nrdbench::Median(ms);
    return median > 0.0 ? 2.0 * double(bytes) / (median * 1e6) : 0.0;
}

// 'probe': the run's timing that carries the bandwidth probe (its first settings variant).
void FillTiming(const nrdlab::RunReport& run, const nrdlab::TimingReport& t, const nrdlab::TimingReport& probe,
                nrdbench::SizeResult& z)
{
    z.width = run.width;
    z.height = run.height;
    z.frames = uint32_t(t.frameMs.size());
    z.warmupFrames = t.warmupFrames;
    z.framesPerSubmission = t.framesPerSubmission;
    z.medianMs = nrdbench::Median(t.frameMs);
    z.p10Ms = nrdbench::Percentile(t.frameMs, 0.1);
    z.p90Ms = nrdbench::Percentile(t.frameMs, 0.9);
    z.minMs = nrdbench::Percentile(t.frameMs, 0.0);
    z.maxMs = nrdbench::Percentile(t.frameMs, 1.0);
    // The device's bandwidth: the faster of the compute and the transfer copy.
    z.computeCopyGBs = Bandwidth(probe.copyBytes, probe.copyMs);
    z.transferCopyGBs = Bandwidth(probe.copyBytes, probe.transferCopyMs);
    z.bandwidthGBs = std::max(z.computeCopyGBs, z.transferCopyGBs);
    z.boundMs = 0.0;
    for (const nrdlab::PassTiming& p : t.passes)
    {
        nrdbench::PassResult pass;
        pass.name = p.name;
        pass.medianMs = nrdbench::Median(p.ms);
        pass.p10Ms = nrdbench::Percentile(p.ms, 0.1);
        pass.p90Ms = nrdbench::Percentile(p.ms, 0.9);
        pass.bytesRead = p.bytes.read;
        pass.bytesWritten = p.bytes.written;
        pass.boundMs = z.bandwidthGBs > 0.0 ? double(p.bytes.Total()) / (z.bandwidthGBs * 1e6) : 0.0;
        z.boundMs += pass.boundMs;
        z.passes.push_back(pass);
    }
    // The pools are created for the render size whatever the settings.
    z.permanentBytes = run.permanentPoolBytes;
    z.transientBytes = run.transientPoolBytes;
    z.bufferBytes = run.bufferPoolBytes;
    z.totalBytes = run.memoryBytes;
    if (!t.aloneMs.empty() && !t.isolatedMs.empty())
    {
        z.submittedAloneMs = nrdbench::Median(t.aloneMs);
        z.isolatedMedianMs = nrdbench::Median(t.isolatedMs);
    }
}

} // namespace

int main(int argc, char** argv)
{
    std::vector<std::string> methods;
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    uint32_t errorWidth = 256, errorHeight = 256;
    bool measureError = true;
    std::string scene = "moving_occluder", outDir = "bench-out", presets = nrdbench::GetBuiltInPresets(), cache;
    uint32_t frames = 0, truthSpp = 256, timedFrames = 64, warmupFrames = 16, warmupMs = 0, perSubmission = 16;
    uint32_t isolatedIdleMs = 0, copyMib = 64, deadlineS = 0, errorJobs = 1;
    int32_t device = -1;
    double budgetMs = -1.0;
    bool quiet = false;

    std::string command = "nrd-bench";
    for (int i = 1; i < argc; i++)
        command += std::string(" ") + argv[i];

    for (int i = 1; i < argc; i++)
    {
        std::string a = argv[i];
        if (a == "--help" || a == "-h")
        {
            PrintUsage();
            return 0;
        }
        if (a == "--list-methods")
        {
            // The methods a run without --methods measures: the library's list.
            const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
            for (uint32_t m = 0; m < lib.supportedMethodsNum; m++)
                std::printf("%s\n", nrd::GetMethodString(lib.supportedMethods[m]));
            return 0;
        }
        if (a == "--quiet")
        {
            quiet = true;
            continue;
        }
        if (i + 1 >= argc)
        {
            std::fprintf(stderr, "error: %s needs a value\n", a.c_str());
            return 2;
        }
        std::string v = argv[++i];
        bool ok = true;
        uint32_t u = 0;
        if (a == "--validate")
        {
            std::string text, error;
            if (!ReadFile(v, text))
            {
                std::fprintf(stderr, "error: cannot read %s\n", v.c_str());
                return 1;
            }
            if (!nrdbench::ValidateReport(text, error))
            {
                std::fprintf(stderr, "error: %s: %s\n", v.c_str(), error.c_str());
                return 1;
            }
            std::printf("%s: valid\n", v.c_str());
            return 0;
        }
        else if (a == "--methods")
            methods = Split(v);
        else if (a == "--sizes")
        {
            sizes.clear();
            for (const std::string& s : Split(v))
            {
                uint32_t w = 0, h = 0;
                ok &= ParseSize(s, w, h);
                sizes.push_back({w, h});
            }
            ok &= !sizes.empty();
        }
        else if (a == "--error-size")
        {
            measureError = v != "none";
            ok = !measureError || ParseSize(v, errorWidth, errorHeight);
        }
        else if (a == "--scene")
            scene = v;
        else if (a == "--frames")
            ok = ParseUint(v, frames) && frames > 0;
        else if (a == "--truth-spp")
            ok = ParseUint(v, truthSpp) && truthSpp > 0;
        else if (a == "--timed-frames")
            ok = ParseUint(v, timedFrames) && timedFrames > 0;
        else if (a == "--warmup-frames")
            ok = ParseUint(v, warmupFrames);
        else if (a == "--warmup-ms")
            ok = ParseUint(v, warmupMs);
        else if (a == "--frames-per-submission")
            ok = ParseUint(v, perSubmission) && perSubmission > 0 && perSubmission <= 64;
        else if (a == "--isolated-idle-ms")
            ok = ParseUint(v, isolatedIdleMs);
        else if (a == "--error-jobs")
            ok = ParseUint(v, errorJobs) && errorJobs > 0 && errorJobs <= 64;
        else if (a == "--deadline-s")
            ok = ParseUint(v, deadlineS);
        else if (a == "--copy-mib")
            ok = ParseUint(v, copyMib) && copyMib > 0 && copyMib <= 4096;
        else if (a == "--budget-ms")
        {
            char* end = nullptr;
            budgetMs = std::strtod(v.c_str(), &end);
            ok = !v.empty() && !*end && budgetMs >= 0.0;
        }
        else if (a == "--presets")
            ok = ReadFile(v, presets);
        else if (a == "--out")
            outDir = v;
        else if (a == "--device")
        {
            ok = ParseUint(v, u);
            device = int32_t(u);
        }
        else if (a == "--cache")
            cache = v;
        else
        {
            std::fprintf(stderr, "error: unknown option %s\n", a.c_str());
            PrintUsage();
            return 2;
        }
        if (!ok)
        {
            std::fprintf(stderr, "error: bad value '%s' for %s\n", v.c_str(), a.c_str());
            return 2;
        }
    }
    if (sizes.empty())
        sizes.push_back({256, 256});
    if (methods.empty())
    {
        const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
        for (uint32_t m = 0; m < lib.supportedMethodsNum; m++)
            methods.push_back(nrd::GetMethodString(lib.supportedMethods[m]));
    }

    // Every (method, setting) first, so that progress can count them.
    nrdbench::BenchReport report;
    report.scene = scene;
    report.sizes = sizes;
    report.budgetMs = budgetMs;
    report.command = command;
    {
        std::time_t now = std::time(nullptr);
        char date[32];
        std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
        report.date = date;
    }
    for (const std::string& method : methods)
    {
        std::vector<nrdbench::Setting> settings;
        std::string error;
        if (!nrdbench::SettingsOfMethod(presets, method, settings, error))
        {
            std::fprintf(stderr, "error: %s\n", error.c_str());
            return 2;
        }
        for (const nrdbench::Setting& s : settings)
        {
            nrdbench::SettingResult r;
            r.method = method;
            r.setting = s.name;
            r.settingsJson = s.settingsJson;
            report.results.push_back(r);
        }
    }

    auto start = std::chrono::steady_clock::now();
    auto progress = [&](size_t k, const nrdbench::SettingResult& r, const std::string& what) {
        if (quiet)
            return;
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::fprintf(stderr, "\r[%zu/%zu %6.1f s] %s / %s: %-40s", k + 1, report.results.size(), s, r.method.c_str(),
                     r.setting.c_str(), what.c_str());
        std::fflush(stderr);
    };

    // Error: one run per setting at the small size (the truth comes from the scene lab's cache
    // after the first). Timing: one run per method and size, every setting timed on the same inputs.
    // --deadline-s: no run starts after it; settings left unmeasured are listed as skipped.
    auto pastDeadline = [&] {
        return deadlineS && std::chrono::steady_clock::now() - start > std::chrono::seconds(deadlineS);
    };
    // One instance and device for every run of the process: drivers keep state per instance and
    // device that they do not all give back (a batch that created one context per run stopped on
    // the H100 with VK_ERROR_INCOMPATIBLE_DRIVER after some thirty of them).
    nrd::lab::VulkanContext context;
    {
        nrd::lab::VulkanContextDesc desc;
        desc.deviceIndex = device;
        desc.quiet = true;
        desc.applicationName = "nrd-bench";
        if (context.Create(desc) != VK_SUCCESS)
        {
            std::fprintf(stderr, "error: could not create a Vulkan device (index %d)\n", device);
            return 1;
        }
    }
    // Error runs first, 'errorJobs' at a time: each worker thread has its own context (a device
    // and a queue; the scene lab and the runner keep no state between runs but the mesh cache, which
    // locks, and the frame cache, whose files are written whole and renamed), so on a GPU the lab's
    // renders, the readbacks and the CPU metrics of several runs overlap. The timing runs follow,
    // one at a time on the main context, with nothing else on the device.
    // What the error runs and the timing runs of a setting share.
    auto baseOptions = [&](const nrdbench::SettingResult& r, nrd::lab::VulkanContext* ctx) {
        nrdlab::RunOptions o;
        o.scene = scene;
        o.method = r.method;
        o.frames = frames;
        o.truthSpp = truthSpp;
        o.device = device;
        o.context = ctx;
        o.keepImages = false;
        return o;
    };
    if (measureError)
    {
        std::atomic<size_t> next{0};
        std::atomic<bool> failed{false};
        std::mutex mutex; // Progress lines and 'firstError'.
        std::string firstError;
        size_t done = 0;
        auto worker = [&](nrd::lab::VulkanContext* shared) {
            nrd::lab::VulkanContext own;
            nrd::lab::VulkanContext* ctx = shared;
            if (!ctx)
            {
                nrd::lab::VulkanContextDesc desc;
                desc.deviceIndex = device;
                desc.quiet = true;
                desc.applicationName = "nrd-bench";
                if (own.Create(desc) != VK_SUCCESS)
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    failed = true;
                    firstError = "could not create a Vulkan device for an error worker";
                    return;
                }
                ctx = &own;
            }
            for (size_t k; !failed && (k = next++) < report.results.size() && !pastDeadline();)
            {
                nrdbench::SettingResult& r = report.results[k];
                nrdlab::RunOptions o = baseOptions(r, ctx);
                o.settingsJson = r.settingsJson;
                o.width = errorWidth;
                o.height = errorHeight;
                o.cacheDirectory = cache;
                const std::string what = "error " + std::to_string(errorWidth) + "x" + std::to_string(errorHeight);
                if (errorJobs == 1)
                    o.progress = [&](uint32_t f, uint32_t n) {
                        progress(k, r, what + ", frame " + std::to_string(f + 1) + "/" + std::to_string(n));
                    };
                nrdlab::RunReport run;
                std::string error;
                if (!nrdlab::RunMethod(o, run, error))
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    if (!failed.exchange(true))
                        firstError = r.method + " / " + r.setting + ": " + error;
                    return;
                }
                nrdbench::QualityResult& q = r.quality;
                q.measured = true;
                q.width = run.width;
                q.height = run.height;
                q.frames = run.frames;
                q.warmup = run.warmup;
                q.truthSpp = run.truthSpp;
                q.relmse = run.mean.relmseDenoised;
                q.relmseNoisy = run.mean.relmseNoisy;
                q.flip = run.mean.flipDenoised;
                q.temporalInstability = run.mean.temporalInstabilityDenoised;
                q.temporalInstabilityTruth = run.mean.temporalInstabilityTruth;
                q.lagFrames = run.lagFrames;
                r.signal = run.signal;
                std::lock_guard<std::mutex> lock(mutex);
                report.device = run.device;
                report.driver = run.driver;
                if (errorJobs > 1 && !quiet)
                {
                    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                    std::fprintf(stderr, "[%zu/%zu %6.1f s] %s / %s: %s measured\n", ++done, report.results.size(), s,
                                 r.method.c_str(), r.setting.c_str(), what.c_str());
                }
            }
        };
        std::vector<std::thread> workers;
        for (uint32_t j = 1; j < errorJobs; j++)
            workers.emplace_back(worker, nullptr);
        worker(&context);
        for (std::thread& t : workers)
            t.join();
        if (failed)
        {
            std::fprintf(stderr, "\nerror: %s\n", firstError.c_str());
            return 1;
        }
    }

    for (size_t k = 0; k < report.results.size() && !pastDeadline(); k++)
    {
        nrdbench::SettingResult& r = report.results[k];
        const nrdlab::RunOptions base = baseOptions(r, &context);
        std::string error;

        // The last setting of a method times them all.
        if (k + 1 < report.results.size() && report.results[k + 1].method == r.method)
            continue;
        size_t first = k;
        while (first > 0 && report.results[first - 1].method == r.method)
            first--;
        for (size_t s = 0; s < sizes.size() && !pastDeadline(); s++)
        {
            nrdlab::RunOptions o = base;
            o.width = sizes[s].first;
            o.height = sizes[s].second;
            // Large frames are not worth a disk cache unless one is named.
            o.cacheDirectory = cache.empty() ? "none" : cache;
            o.timing.frames = timedFrames;
            o.timing.warmupFrames = warmupFrames;
            o.timing.warmupMs = warmupMs;
            o.timing.framesPerSubmission = perSubmission;
            o.timing.skipQuality = true;
            o.timing.copyBytes = uint64_t(copyMib) << 20;
            for (size_t i = first; i <= k; i++)
                o.timing.settingsVariants.push_back(report.results[i].settingsJson);
            o.settingsJson = o.timing.settingsVariants[0];
            // nrd-sample's pattern at the first size only (it idles the GPU for seconds).
            o.timing.isolatedIdleMs = s == 0 ? isolatedIdleMs : 0;
            std::string what = "timing " + std::to_string(o.width) + "x" + std::to_string(o.height);
            o.timing.progress = [&](uint32_t v, uint32_t) { progress(first + v, report.results[first + v], what); };
            progress(first, report.results[first], what);
            auto runStart = std::chrono::steady_clock::now();
            nrdlab::RunReport run;
            if (!nrdlab::RunMethod(o, run, error) || run.timing.size() != k + 1 - first)
            {
                std::fprintf(stderr, "\nerror: %s at %ux%u: %s\n", r.method.c_str(), o.width, o.height, error.c_str());
                return 1;
            }
            double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - runStart).count();
            for (size_t i = first; i <= k; i++)
            {
                const nrdlab::TimingReport& t = run.timing[i - first];
                if (t.frameMs.empty())
                {
                    std::fprintf(stderr, "\nerror: %s: the device has no timestamps\n", run.device.c_str());
                    return 1;
                }
                nrdbench::SizeResult z;
                FillTiming(run, t, run.timing[0], z);
                z.isolatedIdleMs = o.timing.isolatedIdleMs;
                z.runSeconds = seconds;
                report.results[i].sizes.push_back(z);
                report.results[i].signal = run.signal;
            }
            report.device = run.device;
            report.driver = run.driver;
        }
    }
    if (!quiet)
        std::fprintf(stderr, "\n");

    // Only complete settings are reported.
    std::vector<nrdbench::SettingResult> complete;
    for (nrdbench::SettingResult& r : report.results)
    {
        if (r.sizes.size() == sizes.size() && (r.quality.measured || !measureError))
            complete.push_back(std::move(r));
        else
            report.skipped.push_back(r.method + " / " + r.setting);
    }
    report.results = std::move(complete);
    if (!report.skipped.empty())
        std::fprintf(stderr, "deadline: %zu settings skipped\n", report.skipped.size());
    if (report.results.empty())
    {
        std::fprintf(stderr, "error: nothing measured before the deadline\n");
        return 1;
    }
    nrdbench::Analyze(report);
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    std::string json = nrdbench::ToJson(report), markdown = nrdbench::ToMarkdown(report);
    std::ofstream(outDir + "/bench.json") << json << "\n";
    std::ofstream(outDir + "/bench.md") << markdown;
    std::string error;
    std::vector<std::string> plotted;
    std::vector<std::string> measuredMethods;
    for (const nrdbench::SettingResult& r : report.results)
        if (std::find(measuredMethods.begin(), measuredMethods.end(), r.method) == measuredMethods.end())
            measuredMethods.push_back(r.method);
    for (const std::string& method : measuredMethods)
    {
        std::string path = outDir + "/" + method + ".png";
        if (measureError && !nrdbench::WritePlot(path, report, method, error))
        {
            std::fprintf(stderr, "error: plot %s: %s\n", path.c_str(), error.c_str());
            return 1;
        }
    }
    std::printf("%s", markdown.c_str());
    std::printf("report: %s/bench.json, %s/bench.md%s\n", outDir.c_str(), outDir.c_str(),
                measureError ? ", <METHOD>.png per method" : "");
    if (!nrdbench::ValidateReport(json, error))
    {
        // The report is written; say what the validator found (a pass faster than its bound, say).
        std::fprintf(stderr, "warning: %s\n", error.c_str());
    }
    return 0;
}
