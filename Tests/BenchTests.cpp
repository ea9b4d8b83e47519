// nrd-bench: the byte model, the Pareto front, the budget picker, the presets and the report
// schema. Timing is never asserted; the whole tool runs in the nrd_bench_smoke test.
#include "Bench.h"
#include "ByteModel.h"
#include "MethodRunner.h"
#include "VulkanTestUtils.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

using namespace nrd;

TEST_CASE("The byte model equals a hand count on the TILED_SHADOW prepare pass", "[bench]")
{
    const uint16_t w = 61, h = 45; // Odd: the 8x4 tiles round up.
    MethodDesc method = {0, Method::TILED_SHADOW};
    DenoiserCreationDesc desc;
    desc.methods = &method;
    desc.methodsNum = 1;
    desc.renderWidth = w;
    desc.renderHeight = h;
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    REQUIRE(SetCommonSettings(*denoiser, test::StillCameraSettings(0)) == Result::SUCCESS);
    const DispatchDesc* dispatches = nullptr;
    uint32_t dispatchesNum = 0;
    REQUIRE(GetComputeDispatches(*denoiser, nullptr, 0, dispatches, dispatchesNum) == Result::SUCCESS);
    const DispatchDesc* prepare = nullptr;
    for (uint32_t d = 0; d < dispatchesNum; d++)
        if (std::strcmp(dispatches[d].name, "TILED_SHADOW - Prepare") == 0)
            prepare = &dispatches[d];
    REQUIRE(prepare != nullptr);

    // The application's visibility as R8 (1 byte per pixel); the mask is R32_UINT, one texel per
    // 8x4 tile: 8 x 12 tiles for 61 x 45 pixels.
    auto userBytes = [](ResourceType type) { return type == ResourceType::IN_SHADOW_VISIBILITY ? 1u : 0u; };
    nrdlab::DispatchBytes bytes =
        nrdlab::CountDispatchBytes(prepare->resources, prepare->resourcesNum, GetDenoiserDesc(*denoiser), w, h, userBytes);
    CHECK(bytes.read == 61u * 45u * 1u);
    CHECK(bytes.written == 8u * 12u * 4u);
    CHECK(bytes.Total() == 2745u + 384u);
    DestroyDenoiser(denoiser);
}

TEST_CASE("The byte model counts pool buffers and downsampled pool textures", "[bench]")
{
    TextureDesc permanent[1] = {{Format::RGBA16_SFLOAT, 2, 2}};
    TextureDesc transient[1] = {{Format::R8_UNORM, 1, 1}};
    BufferDesc buffers[1] = {{32, false, true}};
    DenoiserDesc desc;
    desc.permanentPool = permanent;
    desc.permanentPoolSize = 1;
    desc.transientPool = transient;
    desc.transientPoolSize = 1;
    desc.buffers = buffers;
    desc.buffersNum = 1;
    ResourceDesc resources[] = {{DescriptorType::TEXTURE, ResourceType::PERMANENT_POOL, 0},
                                {DescriptorType::STORAGE_TEXTURE, ResourceType::TRANSIENT_POOL, 0},
                                {DescriptorType::STORAGE_BUFFER, ResourceType::BUFFER_POOL, 0},
                                {DescriptorType::TEXTURE, ResourceType::IN_VIEWZ, 0},
                                {DescriptorType::TEXTURE, ResourceType::PERMANENT_POOL, 7}}; // Unknown: 0.
    nrdlab::DispatchBytes bytes =
        nrdlab::CountDispatchBytes(resources, 5, desc, 9, 5, [](ResourceType) { return 4u; });
    CHECK(bytes.read == 5u * 3u * 8u + 9u * 5u * 4u);
    CHECK(bytes.written == 9u * 5u * 1u + 32u);
}

TEST_CASE("The Pareto front of a hand-made point set is exact", "[bench]")
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::pair<double, double>> points = {
        {1.0, 0.5},  // front: fastest
        {2.0, 0.2},  // front
        {3.0, 0.1},  // front: most accurate
        {2.5, 0.3},  // slower and worse than {2.0, 0.2}
        {1.0, 0.6},  // as fast as {1.0, 0.5}, worse
        {4.0, 0.1},  // as accurate as {3.0, 0.1}, slower
        {nan, 0.01}, // no time: never on the front
        {0.5, -1.0}, // negative error: never on the front
    };
    std::vector<bool> expected = {true, true, true, false, false, false, false, false};
    CHECK(nrdbench::ParetoFront(points) == expected);
    // Two equal points do not dominate each other.
    CHECK(nrdbench::ParetoFront({{1.0, 1.0}, {1.0, 1.0}}) == std::vector<bool>{true, true});
    CHECK(nrdbench::ParetoFront({}).empty());
}

TEST_CASE("The budget picker returns the cheapest below every time and the most accurate above", "[bench]")
{
    std::vector<std::pair<double, double>> points = {{2.0, 0.2}, {1.0, 0.5}, {3.0, 0.1}, {2.5, 0.3}};
    CHECK(nrdbench::PickForBudget(points, 0.5) == 1);   // Nothing fits: the fastest.
    CHECK(nrdbench::PickForBudget(points, 100.0) == 2); // Everything fits: the most accurate.
    CHECK(nrdbench::PickForBudget(points, 2.7) == 0);   // {2.0, 0.2} beats {2.5, 0.3} and {1.0, 0.5}.
    CHECK(nrdbench::PickForBudget(points, 1.0) == 1);   // The budget itself fits.
    CHECK(nrdbench::PickForBudget({}, 1.0) == -1);
}

TEST_CASE("Presets give every library method at least two settings to trade", "[bench]")
{
    const LibraryDesc& lib = GetLibraryDesc();
    for (uint32_t m = 0; m < lib.supportedMethodsNum; m++)
    {
        const std::string method = GetMethodString(lib.supportedMethods[m]);
        std::vector<nrdbench::Setting> settings;
        std::string error;
        INFO(method << " needs at least two presets in Samples/Bench/Presets.json, the first its defaults "
                       "({\"name\": \"default\", \"settings\": {}}), then settings worth trading (radius, history "
                       "length, pass count, tile skipping, checkerboard...): a method added to the library adds its own");
        REQUIRE(nrdbench::SettingsOfMethod(nrdbench::GetBuiltInPresets(), method, settings, error));
        CHECK(settings.size() >= 2);
        CHECK(settings.front().settingsJson.empty());
    }
    std::vector<nrdbench::Setting> settings;
    std::string error;
    REQUIRE(nrdbench::SettingsOfMethod("{}", "NOT_A_METHOD_YET", settings, error));
    REQUIRE(settings.size() == 1);
    CHECK(settings[0].name == "default");
    CHECK(settings[0].settingsJson.empty());
    CHECK_FALSE(nrdbench::SettingsOfMethod("{\"A\": [{\"name\": \"x\"}, {\"name\": \"x\"}]}", "A", settings, error));
    CHECK_FALSE(nrdbench::SettingsOfMethod("{\"A\": {}}", "A", settings, error));
    CHECK_FALSE(nrdbench::SettingsOfMethod("[", "A", settings, error));
}

namespace
{

nrdbench::BenchReport HandMadeReport()
{
    nrdbench::BenchReport report;
    report.device = "device";
    report.driver = "driver";
    report.date = "today";
    report.command = "nrd-bench";
    report.scene = "static";
    report.sizes = {{64, 32}};
    report.budgetMs = 1.5;
    const double bandwidth = 100.0; // GB/s: 1e8 bytes per ms.
    for (int k = 0; k < 2; k++)
    {
        nrdbench::SettingResult r;
        r.method = "TILED_SHADOW";
        r.setting = k ? "fast" : "default";
        r.settingsJson = k ? "{\"tiledShadow\":{\"atrousPassNum\":1}}" : "";
        r.signal = "shadow";
        r.quality.measured = true;
        r.quality.width = 64;
        r.quality.height = 32;
        r.quality.frames = 8;
        r.quality.truthSpp = 16;
        r.quality.relmse = k ? 0.2 : 0.1;
        nrdbench::SizeResult z;
        z.width = 64;
        z.height = 32;
        z.frames = 10;
        z.framesPerSubmission = 5;
        z.medianMs = k ? 1.0 : 2.0;
        z.p10Ms = z.medianMs * 0.9;
        z.p90Ms = z.medianMs * 1.1;
        z.bandwidthGBs = bandwidth;
        nrdbench::PassResult p;
        p.name = "pass";
        p.medianMs = z.medianMs;
        p.bytesRead = 30000000;
        p.bytesWritten = 20000000;
        p.boundMs = 0.5;
        z.passes.push_back(p);
        z.boundMs = 0.5;
        z.permanentBytes = 100;
        z.totalBytes = 100;
        r.sizes.push_back(z);
        report.results.push_back(r);
    }
    nrdbench::Analyze(report);
    return report;
}

} // namespace

TEST_CASE("The report schema accepts a well-formed report and names what breaks it", "[bench]")
{
    nrdbench::BenchReport report = HandMadeReport();
    REQUIRE(report.results[0].pareto == std::vector<bool>{true});
    REQUIRE(report.results[1].pareto == std::vector<bool>{true});
    REQUIRE(report.picks.size() == 1);
    CHECK(report.picks[0].result == 1); // Only "fast" fits 1.5 ms.
    CHECK(report.picks[0].fits);

    std::string json = nrdbench::ToJson(report), error;
    CHECK(nrdbench::ValidateReport(json, error));
    CHECK(error.empty());
    CHECK(nrdbench::ToMarkdown(report).find("| TILED_SHADOW | fast * | 1.000") != std::string::npos);

    auto broken = [&](const std::function<void(nlohmann::json&)>& change, const char* expected) {
        nlohmann::json j = nlohmann::json::parse(json);
        change(j);
        std::string why;
        CHECK_FALSE(nrdbench::ValidateReport(j.dump(), why));
        CHECK(why.find(expected) != std::string::npos);
    };
    broken([](nlohmann::json& j) { j.erase("device"); }, "device");
    broken([](nlohmann::json& j) { j["schema"] = "other"; }, "schema");
    broken([](nlohmann::json& j) { j["results"][0]["sizes"][0]["passes"][0].erase("bytes_read"); }, "bytes_read");
    broken([](nlohmann::json& j) { j["results"][0]["quality"]["relmse"] = -1.0; }, "relmse");
    broken([](nlohmann::json& j) { j["results"][0]["sizes"][0]["gpu_ms"]["p10"] = 5.0; }, "p10");
    // Faster than the bandwidth allows: a measuring or byte-model error.
    broken(
        [](nlohmann::json& j) {
            j["results"][1]["sizes"][0]["passes"][0]["gpu_ms"]["median"] = 0.25;
        },
        "below the bound");
    broken([](nlohmann::json& j) { j["results"][0]["sizes"][0]["passes"][0]["bound_ms"] = 0.4; }, "bytes / bandwidth");
    broken([](nlohmann::json& j) { j["results"][0]["sizes"].push_back(j["results"][0]["sizes"][0]); }, "one timing per size");
    CHECK_FALSE(nrdbench::ValidateReport("{", error));
}

TEST_CASE("Median and percentiles interpolate between ranks", "[bench]")
{
    CHECK(nrdbench::Median({3.0, 1.0, 2.0}) == 2.0);
    CHECK(nrdbench::Median({4.0, 1.0, 2.0, 3.0}) == Approx(2.5));
    CHECK(nrdbench::Percentile({1.0, 2.0, 3.0, 4.0, 5.0}, 0.1) == Approx(1.4));
    CHECK(nrdbench::Percentile({}, 0.5) == 0.0);
}

namespace
{

// What a process holds: open files, threads, memory mappings (Linux /proc; -1 where unreadable).
struct ProcessHoldings
{
    long files = -1, threads = -1, mappings = -1;
};

ProcessHoldings Holdings()
{
    ProcessHoldings h;
    auto count = [](const char* dir) {
        std::error_code ec;
        long n = 0;
        for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
            n++;
        return ec ? -1 : n;
    };
    h.files = count("/proc/self/fd");
    h.threads = count("/proc/self/task");
    std::ifstream maps("/proc/self/maps");
    std::string line;
    for (h.mappings = 0; std::getline(maps, line);)
        h.mappings++;
    return h;
}

nrdlab::RunOptions SmallErrorRun(const std::string& method)
{
    nrdlab::RunOptions o;
    o.scene = "moving_occluder";
    o.method = method;
    o.width = 24;
    o.height = 16;
    o.frames = 3;
    o.warmup = 1;
    o.truthSpp = 4;
    o.cacheDirectory = "none";
    o.keepImages = false;
    return o;
}

} // namespace

TEST_CASE("Contexts created and destroyed one after the other leave no file, thread or mapping behind", "[bench]")
{
    lab::VulkanContextDesc desc;
    desc.quiet = true;
    // The first contexts load the driver and let the allocator settle its per-thread arenas: the
    // driver's worker threads come and go with each context, and glibc hands an exiting thread's
    // arena to the next one, so the count of mappings wanders by a few lines without any leak.
    for (int i = 0; i < 4; i++)
    {
        lab::VulkanContext warm;
        REQUIRE(warm.Create(desc) == VK_SUCCESS);
    }
    const ProcessHoldings before = Holdings();
    REQUIRE(before.files > 0);
    REQUIRE(before.threads > 0);
    constexpr int kCycles = 24;
    for (int i = 0; i < kCycles; i++)
    {
        lab::VulkanContext context;
        REQUIRE(context.Create(desc) == VK_SUCCESS);
        CHECK(Holdings().threads >= before.threads);
    }
    const ProcessHoldings after = Holdings();
    CHECK(after.files == before.files);
    CHECK(after.threads == before.threads);
    // A context that kept one mapping would add kCycles lines; the allocator's wander stays a few.
    INFO("mappings " << before.mappings << " -> " << after.mappings);
    CHECK(after.mappings < before.mappings + kCycles / 3);
}

TEST_CASE("Error runs of every family in one process share one context and leave nothing behind", "[bench]")
{
    // One method per family the runner knows (a new family's methods run through the same path).
    const std::vector<std::string> methods = {"SIGMA_SHADOW", "TILED_SHADOW", "REFERENCE", "REBLUR_DIFFUSE_SPECULAR",
                                             "CONFIDENCE", "REFLECTION"};
    lab::VulkanContextDesc desc;
    desc.quiet = true;
    lab::VulkanContext context;
    REQUIRE(context.Create(desc) == VK_SUCCESS);

    std::vector<double> firstRound;
    ProcessHoldings before;
    for (int round = 0; round < 2; round++)
    {
        if (round == 1)
            before = Holdings(); // After the first round: pipelines compiled once, caches warm.
        for (size_t m = 0; m < methods.size(); m++)
        {
            nrdlab::RunOptions o = SmallErrorRun(methods[m]);
            o.context = &context;
            nrdlab::RunReport report;
            std::string error;
            INFO(methods[m] << ", round " << round);
            REQUIRE(nrdlab::RunMethod(o, report, error));
            REQUIRE(std::isfinite(report.mean.relmseDenoised));
            // The same run on the same context measures the same error.
            if (round == 0)
                firstRound.push_back(report.mean.relmseDenoised);
            else
                CHECK(report.mean.relmseDenoised == firstRound[m]);
        }
    }
    // Mappings are not compared here: lavapipe compiles each run's pipelines into new pages of
    // executable memory and does not give every page back (its allocator, not a leak of ours: the
    // context test above creates no pipelines and keeps its mappings).
    const ProcessHoldings after = Holdings();
    CHECK(after.files == before.files);
    CHECK(after.threads == before.threads);

    // A run on its own context measures what it measures on the shared one.
    nrdlab::RunReport own;
    std::string error;
    REQUIRE(nrdlab::RunMethod(SmallErrorRun("TILED_SHADOW"), own, error));
    CHECK(own.mean.relmseDenoised == firstRound[1]);
}

TEST_CASE("Error runs in parallel threads, each on its own context, measure what they measure one by one", "[bench]")
{
    // nrd-bench --error-jobs N: the scene lab, the runner and the metrics share nothing between
    // runs but caches that lock or write whole files, so the order and the overlap change nothing.
    const std::vector<std::string> methods = {"SIGMA_SHADOW", "REBLUR_DIFFUSE_SPECULAR", "REFLECTION", "TILED_SHADOW"};
    std::vector<double> sequential, parallel(methods.size(), -1.0);
    for (const std::string& method : methods)
    {
        nrdlab::RunReport report;
        std::string error;
        INFO(method);
        REQUIRE(nrdlab::RunMethod(SmallErrorRun(method), report, error));
        sequential.push_back(report.mean.relmseDenoised);
    }
    std::vector<std::string> errors(methods.size());
    std::vector<std::thread> threads;
    for (size_t t = 0; t < 2; t++)
        threads.emplace_back([&, t] {
            lab::VulkanContextDesc desc;
            desc.quiet = true;
            lab::VulkanContext context;
            if (context.Create(desc) != VK_SUCCESS)
            {
                errors[t] = "no context";
                return;
            }
            for (size_t m = t; m < methods.size(); m += 2) // Thread 0 the even methods, thread 1 the odd ones.
            {
                nrdlab::RunOptions o = SmallErrorRun(methods[m]);
                o.context = &context;
                nrdlab::RunReport report;
                if (nrdlab::RunMethod(o, report, errors[m]))
                    parallel[m] = report.mean.relmseDenoised;
            }
        });
    for (std::thread& t : threads)
        t.join();
    for (size_t m = 0; m < methods.size(); m++)
    {
        INFO(methods[m] << ": " << errors[m]);
        CHECK(std::isfinite(sequential[m]));
        CHECK(parallel[m] == sequential[m]);
    }
}
