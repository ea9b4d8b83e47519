// nrd-bench's model: settings per method, the results of timing and error runs, the Pareto front,
// the budget picker and the report (JSON, Markdown, plots). The runs themselves go through the
// method runner (MethodRunner.h); Main.cpp drives them.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace nrdbench
{

// One setting worth trading: a name and the runner's settings JSON (RunOptions::settingsJson).
struct Setting
{
    std::string name;
    std::string settingsJson;
};

// The settings of 'method' from a presets JSON object {"METHOD": [{"name": ..., "settings": {...}}]}.
// A method the presets do not name gets one setting, "default" (its default settings). Returns
// false with 'error' on malformed presets.
bool SettingsOfMethod(const std::string& presetsJson, const std::string& method, std::vector<Setting>& out,
                      std::string& error);

// The presets built into nrd-bench (Samples/Bench/Presets.json).
const std::string& GetBuiltInPresets();

double Median(std::vector<double> values);
// Linear interpolation between closest ranks, 'p' in [0, 1]; 0 for no values.
double Percentile(std::vector<double> values, double p);

// Points (GPU ms, error): entry i is true if no other point is at most as slow and at most as wrong
// and better in one of them. Non-finite or negative points are never on the front.
std::vector<bool> ParetoFront(const std::vector<std::pair<double, double>>& points);

// Index of the most accurate point (lowest error; the faster on ties) whose time fits 'budgetMs';
// the fastest point if none fits; -1 if there are no points.
int PickForBudget(const std::vector<std::pair<double, double>>& points, double budgetMs);

struct PassResult
{
    std::string name;
    double medianMs = 0, p10Ms = 0, p90Ms = 0;
    uint64_t bytesRead = 0, bytesWritten = 0; // ByteModel.h
    double boundMs = 0;                       // (bytesRead + bytesWritten) / bandwidth
};

struct SizeResult
{
    uint32_t width = 0, height = 0;
    uint32_t frames = 0, warmupFrames = 0, framesPerSubmission = 0;
    double medianMs = 0, p10Ms = 0, p90Ms = 0, minMs = 0, maxMs = 0; // Per frame.
    double boundMs = 0;            // Sum of the passes' bounds.
    double bandwidthGBs = 0;       // The faster copy probe of this run (GB = 1e9 bytes):
    double computeCopyGBs = 0, transferCopyGBs = 0; // a compute dispatch, vkCmdCopyBuffer.
    std::vector<PassResult> passes;
    uint64_t permanentBytes = 0, transientBytes = 0, bufferBytes = 0, totalBytes = 0;
    // One frame per submission, waited for: right away, and after 'isolatedIdleMs' of host idle
    // time (nrd-sample's way, the scene lab and the metrics running between frames); -1: not run.
    double submittedAloneMs = -1, isolatedMedianMs = -1;
    uint32_t isolatedIdleMs = 0;
    double runSeconds = 0;         // Host time of the run that timed every setting of the method at this
                                   // size (context, scene lab, upload, frames).
};

struct QualityResult
{
    bool measured = false;
    uint32_t width = 0, height = 0, frames = 0, warmup = 0, truthSpp = 0;
    double relmse = 0, relmseNoisy = 0, flip = 0, temporalInstability = 0, temporalInstabilityTruth = 0;
    int32_t lagFrames = 0;
};

struct SettingResult
{
    std::string method, setting, settingsJson, signal;
    QualityResult quality;
    std::vector<SizeResult> sizes; // In BenchReport::sizes order.
    std::vector<bool> pareto;      // Per size: on the method's Pareto front (GPU ms, relMSE).
};

struct BenchReport
{
    std::string device, driver, date, command, scene;
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    double budgetMs = -1; // < 0: none asked.
    std::vector<SettingResult> results;
    // Per method and size: the setting picked for the budget ('setting' index into 'results').
    struct Pick
    {
        std::string method;
        uint32_t width = 0, height = 0;
        int result = -1;
        bool fits = false;
    };
    std::vector<Pick> picks;
    std::vector<std::string> skipped; // "METHOD / setting" left unmeasured (nrd-bench --deadline-s).
};

// Fills SettingResult::pareto and BenchReport::picks from the results.
void Analyze(BenchReport& report);

std::string ToJson(const BenchReport& report);
std::string ToMarkdown(const BenchReport& report);

// Checks a JSON report: the schema (every field, its type, one entry per size), and that each
// pass and each setting measured at least its bandwidth bound. False with the first problem.
bool ValidateReport(const std::string& json, std::string& error);

// PNG of relMSE (y, log) against GPU ms per frame (x, log) of one method's settings, one colour
// per size (blue, orange, green, red, ...), with each size's Pareto front joined by a line and its
// points ringed; decade lines labelled 1e-3 etc., lighter lines at 2x and 5x.
bool WritePlot(const std::string& path, const BenchReport& report, const std::string& method, std::string& error);

} // namespace nrdbench
