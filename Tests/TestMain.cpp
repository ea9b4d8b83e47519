// Entry point of every test executable: Catch2's, plus slicing for ctest.
//
// NRD_TEST_SHARD="k/n" (1 <= k <= n) runs only the k-th of n contiguous slices of the test cases
// the command line selects (declaration order), so that one long executable can be n ctest entries
// that `ctest -j` runs side by side (nrd_add_test's SHARDS, Tests/CMakeLists.txt). Contiguous, so
// that neighbouring cases that share a cached setup (the robustness matrix's clean runs of one
// method) stay in one process.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{

bool ParseShard(const char* text, size_t& index, size_t& count)
{
    unsigned k = 0, n = 0;
    char tail = 0;
    if (std::sscanf(text, "%u/%u%c", &k, &n, &tail) != 2 || n == 0 || k == 0 || k > n)
        return false;
    index = k - 1;
    count = n;
    return true;
}

// A test name as a Catch test-spec pattern that matches it exactly.
std::string EscapeName(const std::string& name)
{
    std::string escaped;
    for (char c : name)
    {
        if (c == '\\' || c == ',' || c == '[' || c == ']' || c == '"' || c == '~' || c == '*')
            escaped += '\\';
        escaped += c;
    }
    return escaped;
}

} // namespace

int main(int argc, char* argv[])
{
    Catch::Session session;
    int status = session.applyCommandLine(argc, argv);
    if (status != 0)
        return status;

    const char* shard = std::getenv("NRD_TEST_SHARD");
    if (shard && *shard)
    {
        size_t index = 0, count = 1;
        if (!ParseShard(shard, index, count))
        {
            std::fprintf(stderr, "NRD_TEST_SHARD='%s': expected k/n with 1 <= k <= n\n", shard);
            return 2;
        }
        const Catch::IConfig& config = session.config();
        std::vector<Catch::TestCase> selected =
            Catch::filterTests(Catch::getAllTestCasesSorted(config), config.testSpec(), config);
        const size_t begin = selected.size() * index / count;
        const size_t end = selected.size() * (index + 1) / count;
        Catch::ConfigData data = session.configData();
        data.testsOrTags.clear();
        std::string spec;
        for (size_t i = begin; i < end; i++)
            spec += (spec.empty() ? "" : ",") + EscapeName(selected[i].name);
        std::printf("NRD_TEST_SHARD %zu/%zu: test cases %zu..%zu of %zu\n", index + 1, count, begin + 1, end,
                    selected.size());
        if (begin == end)
            return 0; // More slices than cases: this one has nothing to run.
        data.testsOrTags.push_back(spec);
        session.useConfigData(data);
    }
    return session.run();
}
