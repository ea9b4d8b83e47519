// Entry point of every test executable: Catch2's, plus slicing for ctest.
//
// NRD_TEST_SHARD="k/n" (1 <= k <= n) runs only the k-th of n contiguous slices of the test cases
// the command line selects (declaration order), so that one long executable can be n ctest entries
// that `ctest -j` runs side by side (nrd_add_test's SHARDS, Tests/CMakeLists.txt). Contiguous, so
// that neighbouring cases that share a cached setup (the robustness matrix's clean runs of one
// method) stay in one process.
//
// A fatal signal (a crash in the Vulkan driver, a heap corruption that glibc aborts on) ends the
// process at once, after naming the test case it ran: Catch's own handler reports through the
// reporter, which allocates, and a process aborted inside malloc then deadlocks on the heap's lock
// until ctest's timeout (15 minutes lost, and no name). CrashNamer writes with write(2) only.
// Under AddressSanitizer its own handlers stay (they report the faulting access).
#define CATCH_CONFIG_RUNNER
#define CATCH_CONFIG_NO_POSIX_SIGNALS
#define CATCH_CONFIG_EXTERNAL_INTERFACES
#include <catch2/catch.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define NRD_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NRD_TEST_UNDER_ASAN 1
#endif
#endif
#ifndef NRD_TEST_UNDER_ASAN
#define NRD_TEST_UNDER_ASAN 0
#endif

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

// The running test case's name, for the signal handler (a fixed buffer: no allocation there).
char g_CurrentTest[512] = "(before the first test case)";

void WriteAll(const char* text)
{
    size_t length = std::strlen(text);
    while (length > 0)
    {
        ssize_t written = write(STDERR_FILENO, text, length);
        if (written <= 0)
            return;
        text += written;
        length -= (size_t)written;
    }
}

extern "C" [[maybe_unused]] void OnFatalSignal(int signal)
{
    WriteAll("\nFatal signal ");
    WriteAll(signal == SIGABRT ? "SIGABRT" : signal == SIGSEGV ? "SIGSEGV" : signal == SIGBUS ? "SIGBUS"
             : signal == SIGFPE ? "SIGFPE" : signal == SIGILL ? "SIGILL" : "(other)");
    WriteAll(" in test case: ");
    WriteAll(g_CurrentTest);
    WriteAll("\n");
    std::signal(signal, SIG_DFL); // Then die of it (core dump, ctest's "exception" status).
    std::raise(signal);
}

struct CrashNamer : Catch::TestEventListenerBase
{
    using TestEventListenerBase::TestEventListenerBase;
    void testCaseStarting(Catch::TestCaseInfo const& info) override
    {
        std::snprintf(g_CurrentTest, sizeof(g_CurrentTest), "%s", info.name.c_str());
        TestEventListenerBase::testCaseStarting(info);
    }
};

} // namespace

CATCH_REGISTER_LISTENER(CrashNamer)

int main(int argc, char* argv[])
{
#if !NRD_TEST_UNDER_ASAN
    for (int signal : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL})
        std::signal(signal, OnFatalSignal);
#endif

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
