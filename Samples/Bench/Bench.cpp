#include "Bench.h"

#include "Image.h"
#include "ImageIO.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

namespace nrdbench
{

extern const char* const kBuiltInPresets; // Generated from Presets.json (CMakeLists.txt).

const std::string& GetBuiltInPresets()
{
    static const std::string presets = kBuiltInPresets;
    return presets;
}

bool SettingsOfMethod(const std::string& presetsJson, const std::string& method, std::vector<Setting>& out,
                      std::string& error)
{
    out.clear();
    try
    {
        nlohmann::json j = presetsJson.empty() ? nlohmann::json::object() : nlohmann::json::parse(presetsJson);
        if (!j.is_object())
        {
            error = "presets: the top level must be an object of methods";
            return false;
        }
        if (j.contains(method))
        {
            const nlohmann::json& list = j.at(method);
            if (!list.is_array())
            {
                error = "presets: " + method + " must be an array";
                return false;
            }
            std::set<std::string> names;
            for (const nlohmann::json& entry : list)
            {
                if (!entry.is_object() || !entry.contains("name") || !entry.at("name").is_string())
                {
                    error = "presets: every entry of " + method + " needs a \"name\"";
                    return false;
                }
                Setting s;
                s.name = entry.at("name").get<std::string>();
                if (!names.insert(s.name).second)
                {
                    error = "presets: " + method + " names '" + s.name + "' twice";
                    return false;
                }
                nlohmann::json settings = entry.value("settings", nlohmann::json::object());
                if (!settings.is_object())
                {
                    error = "presets: settings of " + method + " / " + s.name + " must be an object";
                    return false;
                }
                s.settingsJson = settings.empty() ? "" : settings.dump();
                out.push_back(s);
            }
        }
    }
    catch (const std::exception& e)
    {
        error = std::string("presets: ") + e.what();
        return false;
    }
    if (out.empty())
        out.push_back({"default", ""});
    return true;
}

double Percentile(std::vector<double> values, double p)
{
    if (values.empty())
        return 0.0;
    std::sort(values.begin(), values.end());
    double rank = std::min(std::max(p, 0.0), 1.0) * double(values.size() - 1);
    size_t lo = size_t(rank);
    size_t hi = std::min(lo + 1, values.size() - 1);
    return values[lo] + (values[hi] - values[lo]) * (rank - double(lo));
}

double Median(std::vector<double> values)
{
    return Percentile(std::move(values), 0.5);
}

namespace
{

bool Usable(const std::pair<double, double>& p)
{
    return std::isfinite(p.first) && std::isfinite(p.second) && p.first >= 0.0 && p.second >= 0.0;
}

} // namespace

std::vector<bool> ParetoFront(const std::vector<std::pair<double, double>>& points)
{
    std::vector<bool> front(points.size(), false);
    for (size_t i = 0; i < points.size(); i++)
    {
        if (!Usable(points[i]))
            continue;
        bool dominated = false;
        for (size_t j = 0; j < points.size() && !dominated; j++)
        {
            if (j == i || !Usable(points[j]))
                continue;
            const auto& a = points[j];
            const auto& b = points[i];
            dominated = a.first <= b.first && a.second <= b.second && (a.first < b.first || a.second < b.second);
        }
        front[i] = !dominated;
    }
    return front;
}

int PickForBudget(const std::vector<std::pair<double, double>>& points, double budgetMs)
{
    int best = -1, fastest = -1;
    for (size_t i = 0; i < points.size(); i++)
    {
        const auto& p = points[i];
        if (!Usable(p))
            continue;
        if (fastest < 0 || p.first < points[fastest].first)
            fastest = int(i);
        if (p.first > budgetMs)
            continue;
        if (best < 0 || p.second < points[best].second ||
            (p.second == points[best].second && p.first < points[best].first))
            best = int(i);
    }
    return best >= 0 ? best : fastest;
}

void Analyze(BenchReport& report)
{
    std::vector<std::string> methods;
    for (const SettingResult& r : report.results)
        if (std::find(methods.begin(), methods.end(), r.method) == methods.end())
            methods.push_back(r.method);
    for (SettingResult& r : report.results)
        r.pareto.assign(report.sizes.size(), false);
    report.picks.clear();
    for (const std::string& method : methods)
    {
        for (size_t s = 0; s < report.sizes.size(); s++)
        {
            std::vector<std::pair<double, double>> points;
            std::vector<size_t> index;
            for (size_t i = 0; i < report.results.size(); i++)
            {
                const SettingResult& r = report.results[i];
                if (r.method != method || s >= r.sizes.size())
                    continue;
                // Without an error measurement a setting still has a place on the time axis.
                points.push_back({r.sizes[s].medianMs, r.quality.measured ? r.quality.relmse : 0.0});
                index.push_back(i);
            }
            std::vector<bool> front = ParetoFront(points);
            for (size_t k = 0; k < index.size(); k++)
                report.results[index[k]].pareto[s] = front[k];
            if (report.budgetMs >= 0.0)
            {
                BenchReport::Pick pick;
                pick.method = method;
                pick.width = report.sizes[s].first;
                pick.height = report.sizes[s].second;
                int k = PickForBudget(points, report.budgetMs);
                pick.result = k >= 0 ? int(index[k]) : -1;
                pick.fits = k >= 0 && points[k].first <= report.budgetMs;
                report.picks.push_back(pick);
            }
        }
    }
}

std::string ToJson(const BenchReport& report)
{
    nlohmann::json j;
    j["schema"] = "nrd-bench/1";
    j["device"] = report.device;
    j["driver"] = report.driver;
    j["date"] = report.date;
    j["command"] = report.command;
    j["scene"] = report.scene;
    j["sizes"] = nlohmann::json::array();
    for (const auto& s : report.sizes)
        j["sizes"].push_back({{"width", s.first}, {"height", s.second}});
    j["results"] = nlohmann::json::array();
    for (const SettingResult& r : report.results)
    {
        nlohmann::json e;
        e["method"] = r.method;
        e["setting"] = r.setting;
        e["settings"] = r.settingsJson.empty() ? nlohmann::json::object() : nlohmann::json::parse(r.settingsJson);
        e["signal"] = r.signal;
        const QualityResult& q = r.quality;
        nlohmann::json quality = nullptr;
        if (q.measured)
            quality = {{"width", q.width},
                       {"height", q.height},
                       {"frames", q.frames},
                       {"warmup", q.warmup},
                       {"truth_spp", q.truthSpp},
                       {"relmse", q.relmse},
                       {"relmse_noisy", q.relmseNoisy},
                       {"flip", q.flip},
                       {"temporal_instability", q.temporalInstability},
                       {"temporal_instability_truth", q.temporalInstabilityTruth},
                       {"lag_frames", q.lagFrames}};
        e["quality"] = quality;
        e["sizes"] = nlohmann::json::array();
        for (size_t s = 0; s < r.sizes.size(); s++)
        {
            const SizeResult& z = r.sizes[s];
            nlohmann::json t;
            t["width"] = z.width;
            t["height"] = z.height;
            t["frames"] = z.frames;
            t["warmup_frames"] = z.warmupFrames;
            t["frames_per_submission"] = z.framesPerSubmission;
            t["gpu_ms"] = {{"median", z.medianMs}, {"p10", z.p10Ms}, {"p90", z.p90Ms}, {"min", z.minMs}, {"max", z.maxMs}};
            t["bound_ms"] = z.boundMs;
            t["measured_over_bound"] = z.boundMs > 0.0 ? z.medianMs / z.boundMs : 0.0;
            t["bandwidth_gbs"] = z.bandwidthGBs;
            t["copy_gbs"] = {{"compute", z.computeCopyGBs}, {"transfer", z.transferCopyGBs}};
            t["memory_bytes"] = {{"permanent", z.permanentBytes},
                                 {"transient", z.transientBytes},
                                 {"buffers", z.bufferBytes},
                                 {"total", z.totalBytes}};
            t["alone_gpu_ms"] = z.submittedAloneMs >= 0.0 ? nlohmann::json(z.submittedAloneMs) : nlohmann::json(nullptr);
            t["isolated_gpu_ms"] = z.isolatedMedianMs >= 0.0 ? nlohmann::json(z.isolatedMedianMs) : nlohmann::json(nullptr);
            t["isolated_idle_ms"] = z.isolatedIdleMs;
            t["run_seconds"] = z.runSeconds;
            t["pareto"] = s < r.pareto.size() && r.pareto[s];
            t["passes"] = nlohmann::json::array();
            for (const PassResult& p : z.passes)
                t["passes"].push_back({{"name", p.name},
                                       {"gpu_ms", {{"median", p.medianMs}, {"p10", p.p10Ms}, {"p90", p.p90Ms}}},
                                       {"bytes_read", p.bytesRead},
                                       {"bytes_written", p.bytesWritten},
                                       {"bound_ms", p.boundMs},
                                       {"measured_over_bound", p.boundMs > 0.0 ? p.medianMs / p.boundMs : 0.0}});
            e["sizes"].push_back(t);
        }
        j["results"].push_back(e);
    }
    j["skipped"] = report.skipped;
    if (report.budgetMs >= 0.0)
    {
        j["budget_ms"] = report.budgetMs;
        j["budget_picks"] = nlohmann::json::array();
        for (const BenchReport::Pick& p : report.picks)
        {
            nlohmann::json e = {{"method", p.method}, {"width", p.width}, {"height", p.height}, {"fits", p.fits}};
            e["setting"] = p.result >= 0 ? nlohmann::json(report.results[p.result].setting) : nlohmann::json(nullptr);
            j["budget_picks"].push_back(e);
        }
    }
    return j.dump(2);
}

namespace
{

std::string Format(const char* format, double value)
{
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), format, value);
    return buffer;
}

std::string Mb(uint64_t bytes)
{
    return Format("%.2f", double(bytes) / 1e6);
}

} // namespace

std::string ToMarkdown(const BenchReport& report)
{
    std::ostringstream md;
    md << "Device: " << report.device << " (" << report.driver << "), " << report.date << ".\n\n";
    md << "Command: `" << report.command << "`\n\n";
    bool anyQuality = false;
    for (const SettingResult& r : report.results)
        if (r.quality.measured)
        {
            md << "Error against the scene lab's truth on `" << report.scene << "` at " << r.quality.width << "x"
               << r.quality.height << ", " << r.quality.frames << " frames (the first " << r.quality.warmup
               << " not averaged), truth " << r.quality.truthSpp << " spp. ";
            anyQuality = true;
            break;
        }
    md << "GPU time per frame: median (10th - 90th percentile) of the timed frames, recorded back to back after the "
          "warm-up on fixed inputs. Bound: minimal bytes / copy bandwidth of the same run. * on the Pareto front "
          "(GPU time, relMSE) of its method.\n\n";
    if (!anyQuality)
        md << "(No error measured in this run.)\n\n";

    for (size_t s = 0; s < report.sizes.size(); s++)
    {
        md << "### " << report.sizes[s].first << "x" << report.sizes[s].second << "\n\n";
        md << "| method | setting | GPU ms | bound ms | measured / bound | memory MB (perm + trans + buf) | relMSE "
              "(noisy) | FLIP | temporal instability | lag |\n";
        md << "|---|---|---|---|---|---|---|---|---|---|\n";
        for (size_t i = 0; i < report.results.size(); i++)
        {
            const SettingResult& r = report.results[i];
            if (s >= r.sizes.size())
                continue;
            const SizeResult& z = r.sizes[s];
            const QualityResult& q = r.quality;
            bool front = s < r.pareto.size() && r.pareto[s];
            md << "| " << r.method << " | " << r.setting << (front ? " *" : "") << " | " << Format("%.3f", z.medianMs)
               << " (" << Format("%.3f", z.p10Ms) << " - " << Format("%.3f", z.p90Ms) << ") | "
               << Format("%.3f", z.boundMs) << " | " << (z.boundMs > 0 ? Format("%.1f", z.medianMs / z.boundMs) : "-")
               << " | " << Mb(z.totalBytes) << " (" << Mb(z.permanentBytes) << " + " << Mb(z.transientBytes) << " + "
               << Mb(z.bufferBytes) << ") | ";
            if (q.measured)
                md << Format("%.5f", q.relmse) << " (" << Format("%.4f", q.relmseNoisy) << ") | "
                   << Format("%.4f", q.flip) << " | " << Format("%.5f", q.temporalInstability) << " | " << q.lagFrames
                   << " |\n";
            else
                md << "- | - | - | - |\n";
        }
        md << "\n";
    }

    // Per pass, the first setting of each method (its defaults).
    md << "Per pass (first setting of each method): GPU ms median, minimal MB moved, measured / bound.\n\n";
    md << "| method | size | pass | GPU ms | MB read + written | measured / bound |\n|---|---|---|---|---|---|\n";
    std::set<std::string> seen;
    for (const SettingResult& r : report.results)
    {
        if (!seen.insert(r.method).second)
            continue;
        for (const SizeResult& z : r.sizes)
            for (const PassResult& p : z.passes)
                md << "| " << r.method << " | " << z.width << "x" << z.height << " | " << p.name << " | "
                   << Format("%.3f", p.medianMs) << " | " << Mb(p.bytesRead) << " + " << Mb(p.bytesWritten) << " | "
                   << (p.boundMs > 0 ? Format("%.1f", p.medianMs / p.boundMs) : "-") << " |\n";
    }
    md << "\n";

    bool anyIsolated = false;
    for (const SettingResult& r : report.results)
        for (const SizeResult& z : r.sizes)
            anyIsolated |= z.isolatedMedianMs >= 0.0;
    if (anyIsolated)
    {
        md << "Back to back against one frame per submission, waited for, right away and after host idle time (as "
              "nrd-sample runs: the scene lab and the metrics between frames), first setting of each method, median "
              "of 8 frames:\n\n";
        md << "| method | size | back to back ms | one per submission ms | after idle ms | host idle ms | after idle / "
              "back to back |\n|---|---|---|---|---|---|---|\n";
        for (const SettingResult& r : report.results)
            for (const SizeResult& z : r.sizes)
                if (z.isolatedMedianMs >= 0.0)
                    md << "| " << r.method << " | " << z.width << "x" << z.height << " | " << Format("%.3f", z.medianMs)
                       << " | " << Format("%.3f", z.submittedAloneMs) << " | " << Format("%.3f", z.isolatedMedianMs)
                       << " | " << z.isolatedIdleMs << " | "
                       << (z.medianMs > 0 ? Format("%.2f", z.isolatedMedianMs / z.medianMs) : "-") << " |\n";
        md << "\n";
    }

    if (!report.skipped.empty())
    {
        md << "Not measured (deadline):";
        for (const std::string& name : report.skipped)
            md << " " << name << ";";
        md << "\n\n";
    }

    if (report.budgetMs >= 0.0)
    {
        md << "Budget " << Format("%.3f", report.budgetMs) << " ms: the most accurate setting that fits.\n\n";
        md << "| method | size | setting | fits |\n|---|---|---|---|\n";
        for (const BenchReport::Pick& p : report.picks)
            md << "| " << p.method << " | " << p.width << "x" << p.height << " | "
               << (p.result >= 0 ? report.results[p.result].setting : "-") << " | "
               << (p.fits ? "yes" : "no (fastest shown)") << " |\n";
        md << "\n";
    }
    return md.str();
}

bool ValidateReport(const std::string& text, std::string& error)
{
    try
    {
        nlohmann::json j = nlohmann::json::parse(text);
        auto need = [&](const nlohmann::json& o, const char* key, nlohmann::json::value_t type, const std::string& where) {
            if (!o.is_object() || !o.contains(key))
                throw std::runtime_error(where + ": missing \"" + key + "\"");
            const nlohmann::json& v = o.at(key);
            bool ok = v.type() == type || (type == nlohmann::json::value_t::number_float && v.is_number()) ||
                      (type == nlohmann::json::value_t::number_unsigned && v.is_number_unsigned());
            if (!ok)
                throw std::runtime_error(where + ": \"" + key + "\" has the wrong type");
            return v;
        };
        using T = nlohmann::json::value_t;
        if (need(j, "schema", T::string, "report").get<std::string>() != "nrd-bench/1")
            throw std::runtime_error("report: unknown schema");
        for (const char* key : {"device", "driver", "date", "command", "scene"})
            need(j, key, T::string, "report");
        need(j, "skipped", T::array, "report");
        size_t sizesNum = need(j, "sizes", T::array, "report").size();
        if (!sizesNum)
            throw std::runtime_error("report: no sizes");
        const nlohmann::json& results = need(j, "results", T::array, "report");
        if (results.empty())
            throw std::runtime_error("report: no results");
        for (const nlohmann::json& r : results)
        {
            std::string where = "result";
            where += " " + need(r, "method", T::string, where).get<std::string>();
            where += " / " + need(r, "setting", T::string, where).get<std::string>();
            need(r, "settings", T::object, where);
            need(r, "signal", T::string, where);
            if (!r.contains("quality"))
                throw std::runtime_error(where + ": missing \"quality\"");
            const nlohmann::json& q = r.at("quality");
            if (!q.is_null())
            {
                for (const char* key : {"relmse", "relmse_noisy", "flip", "temporal_instability", "temporal_instability_truth"})
                {
                    double v = need(q, key, T::number_float, where + " quality").get<double>();
                    if (!std::isfinite(v) || v < 0.0)
                        throw std::runtime_error(where + " quality: " + key + " is not a finite value >= 0");
                }
                for (const char* key : {"width", "height", "frames", "truth_spp"})
                    need(q, key, T::number_unsigned, where + " quality");
                if (!q.contains("lag_frames") || !q.at("lag_frames").is_number_integer())
                    throw std::runtime_error(where + " quality: missing integer \"lag_frames\"");
            }
            const nlohmann::json& sizes = need(r, "sizes", T::array, where);
            if (sizes.size() != sizesNum)
                throw std::runtime_error(where + ": one timing per size expected");
            for (const nlohmann::json& z : sizes)
            {
                std::string at = where + " at " + std::to_string(need(z, "width", T::number_unsigned, where).get<uint32_t>()) +
                                 "x" + std::to_string(need(z, "height", T::number_unsigned, where).get<uint32_t>());
                need(z, "frames", T::number_unsigned, at);
                need(z, "frames_per_submission", T::number_unsigned, at);
                const nlohmann::json& gpu = need(z, "gpu_ms", T::object, at);
                double median = need(gpu, "median", T::number_float, at).get<double>();
                double p10 = need(gpu, "p10", T::number_float, at).get<double>();
                double p90 = need(gpu, "p90", T::number_float, at).get<double>();
                if (!(median > 0.0) || !(p10 <= median) || !(median <= p90))
                    throw std::runtime_error(at + ": GPU times must satisfy 0 < p10 <= median <= p90");
                double bound = need(z, "bound_ms", T::number_float, at).get<double>();
                double bandwidth = need(z, "bandwidth_gbs", T::number_float, at).get<double>();
                if (!(bandwidth > 0.0) || !(bound > 0.0))
                    throw std::runtime_error(at + ": no bandwidth bound");
                if (median < bound)
                    throw std::runtime_error(at + ": measured " + std::to_string(median) + " ms below the bound " +
                                             std::to_string(bound) + " ms");
                const nlohmann::json& memory = need(z, "memory_bytes", T::object, at);
                uint64_t sum = 0;
                for (const char* key : {"permanent", "transient", "buffers"})
                    sum += need(memory, key, T::number_unsigned, at + " memory").get<uint64_t>();
                if (need(memory, "total", T::number_unsigned, at + " memory").get<uint64_t>() < sum)
                    throw std::runtime_error(at + ": memory total below its parts");
                need(z, "pareto", T::boolean, at);
                double boundSum = 0.0;
                const nlohmann::json& passes = need(z, "passes", T::array, at);
                if (passes.empty())
                    throw std::runtime_error(at + ": no passes");
                for (const nlohmann::json& p : passes)
                {
                    std::string pass = at + " pass " + need(p, "name", T::string, at).get<std::string>();
                    double ms = need(need(p, "gpu_ms", T::object, pass), "median", T::number_float, pass).get<double>();
                    uint64_t bytes = need(p, "bytes_read", T::number_unsigned, pass).get<uint64_t>() +
                                     need(p, "bytes_written", T::number_unsigned, pass).get<uint64_t>();
                    double passBound = need(p, "bound_ms", T::number_float, pass).get<double>();
                    if (std::fabs(passBound - double(bytes) / (bandwidth * 1e6)) > 1e-6 * std::max(1.0, passBound))
                        throw std::runtime_error(pass + ": bound is not bytes / bandwidth");
                    if (ms < passBound)
                        throw std::runtime_error(pass + ": measured " + std::to_string(ms) + " ms below the bound " +
                                                 std::to_string(passBound) + " ms");
                    boundSum += passBound;
                }
                if (std::fabs(boundSum - bound) > 1e-6 * std::max(1.0, bound))
                    throw std::runtime_error(at + ": bound is not the sum of the passes' bounds");
            }
        }
        if (j.contains("budget_ms"))
            for (const nlohmann::json& p : need(j, "budget_picks", T::array, "report"))
            {
                need(p, "method", T::string, "budget pick");
                need(p, "fits", T::boolean, "budget pick");
            }
    }
    catch (const std::exception& e)
    {
        error = e.what();
        return false;
    }
    return true;
}

// ------------------------------------------------------------------------------------------------
// Plot

namespace
{

struct Canvas
{
    nrdlab::Image image;
    void Set(int x, int y, const float c[3])
    {
        if (x < 0 || y < 0 || x >= int(image.width) || y >= int(image.height))
            return;
        for (int k = 0; k < 3; k++)
            image.at(uint32_t(x), uint32_t(y), uint32_t(k)) = c[k];
    }
    void Line(int x0, int y0, int x1, int y1, const float c[3], int thickness = 1)
    {
        int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
        int err = dx + dy;
        for (;;)
        {
            for (int t = 0; t < thickness; t++)
                for (int u = 0; u < thickness; u++)
                    Set(x0 + t - thickness / 2, y0 + u - thickness / 2, c);
            if (x0 == x1 && y0 == y1)
                break;
            int e2 = 2 * err;
            if (e2 >= dy)
            {
                err += dy;
                x0 += sx;
            }
            if (e2 <= dx)
            {
                err += dx;
                y0 += sy;
            }
        }
    }
    void Square(int x, int y, int r, const float c[3])
    {
        for (int v = -r; v <= r; v++)
            for (int u = -r; u <= r; u++)
                Set(x + u, y + v, c);
    }
    void Ring(int x, int y, int r, const float c[3])
    {
        for (int a = 0; a < 64; a++)
        {
            double t = a * 6.283185307 / 64.0;
            Set(x + int(std::lround(r * std::cos(t))), y + int(std::lround(r * std::sin(t))), c);
        }
    }
    // 3x5 glyphs for tick labels: digits, '-', '.', 'e'; 2x scale.
    void Text(int x, int y, const std::string& s, const float c[3])
    {
        static const std::map<char, const char*> glyphs = {
            {'0', "111101101101111"}, {'1', "010110010010111"}, {'2', "111001111100111"}, {'3', "111001111001111"},
            {'4', "101101111001001"}, {'5', "111100111001111"}, {'6', "111100111101111"}, {'7', "111001001001001"},
            {'8', "111101111101111"}, {'9', "111101111001111"}, {'-', "000000111000000"}, {'.', "000000000000010"},
            {'e', "000111101110111"}};
        for (char ch : s)
        {
            auto it = glyphs.find(ch);
            if (it != glyphs.end())
                for (int v = 0; v < 5; v++)
                    for (int u = 0; u < 3; u++)
                        if (it->second[v * 3 + u] == '1')
                            Square(x + u * 2, y + v * 2, 0, c), Square(x + u * 2 + 1, y + v * 2, 0, c),
                                Square(x + u * 2, y + v * 2 + 1, 0, c), Square(x + u * 2 + 1, y + v * 2 + 1, 0, c);
            x += 8;
        }
    }
};

} // namespace

bool WritePlot(const std::string& path, const BenchReport& report, const std::string& method, std::string& error)
{
    const int W = 640, H = 440, left = 70, right = 20, top = 20, bottom = 50;
    Canvas canvas;
    canvas.image = nrdlab::Image(W, H, 3, 1.0f);
    static const float colours[][3] = {{0.12f, 0.47f, 0.71f}, {1.0f, 0.5f, 0.05f}, {0.17f, 0.63f, 0.17f},
                                       {0.84f, 0.15f, 0.16f}, {0.58f, 0.4f, 0.74f}, {0.55f, 0.34f, 0.29f}};
    const float black[3] = {0, 0, 0}, grey[3] = {0.85f, 0.85f, 0.85f};

    // Log-log ranges over every measured point of the method, padded to whole decades.
    double xMin = 1e30, xMax = 0, yMin = 1e30, yMax = 0;
    for (const SettingResult& r : report.results)
        if (r.method == method && r.quality.measured)
            for (const SizeResult& z : r.sizes)
                if (z.medianMs > 0 && r.quality.relmse > 0)
                {
                    xMin = std::min(xMin, z.medianMs), xMax = std::max(xMax, z.medianMs);
                    yMin = std::min(yMin, r.quality.relmse), yMax = std::max(yMax, r.quality.relmse);
                }
    if (xMax <= 0 || yMax <= 0)
    {
        // Nothing to place on log scales (an exact method, say): empty axes over one decade.
        xMin = xMax = 1.0;
        yMin = yMax = 0.01;
    }
    double lx0 = std::floor(std::log10(xMin)), lx1 = std::ceil(std::log10(xMax) + 1e-9);
    double ly0 = std::floor(std::log10(yMin)), ly1 = std::ceil(std::log10(yMax) + 1e-9);
    lx1 = std::max(lx1, lx0 + 1), ly1 = std::max(ly1, ly0 + 1);
    auto px = [&](double ms) { return left + int((std::log10(ms) - lx0) / (lx1 - lx0) * (W - left - right)); };
    auto py = [&](double e) { return H - bottom - int((std::log10(e) - ly0) / (ly1 - ly0) * (H - top - bottom)); };

    const float light[3] = {0.94f, 0.94f, 0.94f};
    for (double d = lx0; d < lx1 - 1e-9; d++)
        for (double m : {2.0, 5.0})
            canvas.Line(px(m * std::pow(10.0, d)), top, px(m * std::pow(10.0, d)), H - bottom, light);
    for (double d = ly0; d < ly1 - 1e-9; d++)
        for (double m : {2.0, 5.0})
            canvas.Line(left, py(m * std::pow(10.0, d)), W - right, py(m * std::pow(10.0, d)), light);
    for (double d = lx0; d <= lx1 + 1e-9; d++)
    {
        canvas.Line(px(std::pow(10.0, d)), top, px(std::pow(10.0, d)), H - bottom, grey);
        canvas.Text(px(std::pow(10.0, d)) - 12, H - bottom + 10, "1e" + std::to_string(int(d)), black);
    }
    for (double d = ly0; d <= ly1 + 1e-9; d++)
    {
        canvas.Line(left, py(std::pow(10.0, d)), W - right, py(std::pow(10.0, d)), grey);
        canvas.Text(8, py(std::pow(10.0, d)) - 5, "1e" + std::to_string(int(d)), black);
    }
    canvas.Line(left, top, left, H - bottom, black, 2);
    canvas.Line(left, H - bottom, W - right, H - bottom, black, 2);

    for (size_t s = 0; s < report.sizes.size(); s++)
    {
        const float* c = colours[s % 6];
        std::vector<std::pair<int, int>> front;
        for (const SettingResult& r : report.results)
        {
            if (r.method != method || !r.quality.measured || s >= r.sizes.size() || r.sizes[s].medianMs <= 0 ||
                r.quality.relmse <= 0)
                continue;
            int x = px(r.sizes[s].medianMs), y = py(r.quality.relmse);
            canvas.Square(x, y, 3, c);
            if (s < r.pareto.size() && r.pareto[s])
            {
                canvas.Ring(x, y, 8, c);
                canvas.Ring(x, y, 9, c);
                front.push_back({x, y});
            }
        }
        std::sort(front.begin(), front.end());
        for (size_t k = 1; k < front.size(); k++)
            canvas.Line(front[k - 1].first, front[k - 1].second, front[k].first, front[k].second, c, 2);
    }
    nrdlab::PngOptions png;
    png.toneMap = false;
    png.srgb = false;
    return nrdlab::WritePng(path, canvas.image, &error, png);
}

} // namespace nrdbench
