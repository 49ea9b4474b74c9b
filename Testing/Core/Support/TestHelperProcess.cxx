// Helper processes: input, output, crashes, hangs and runaway answers.
#include "Support/HelperProcess.h"

#include <gtest/gtest.h>

#include <string>

using namespace beltrami;

namespace
{
std::string Text(const HelperProcessResult& r)
{
  return std::string(r.Output.begin(), r.Output.end());
}
} // namespace

TEST(HelperProcess, InputInOutputOut)
{
  const std::string text = "the input\nof the helper";
  std::vector<char> input(text.begin(), text.end());
  input.resize(3 << 20, 'x'); // larger than a pipe buffer
  const HelperProcessResult r = RunHelperProcess("/bin/cat", {}, input, 1e8, 10.0);
  EXPECT_EQ(r.ExitCode, 0);
  EXPECT_EQ(r.Signal, 0);
  EXPECT_EQ(r.Output, input);
  const HelperProcessResult e = RunHelperProcess("/bin/sh", { "-c", "printf abc; exit 3" }, {}, 1e8, 10.0);
  EXPECT_EQ(Text(e), "abc");
  EXPECT_EQ(e.ExitCode, 3);
}

TEST(HelperProcess, CrashesHangsAndFloodsAreReported)
{
  const HelperProcessResult crash = RunHelperProcess("/bin/sh", { "-c", "kill -SEGV $$" }, {}, 1e8, 10.0);
  EXPECT_EQ(crash.Signal, 11);
  const HelperProcessResult hang = RunHelperProcess("/bin/sh", { "-c", "sleep 30" }, {}, 1e8, 0.5);
  EXPECT_TRUE(hang.TimedOut);
  EXPECT_NE(hang.Signal, 0);
  const HelperProcessResult flood = RunHelperProcess("/bin/cat", { "/dev/zero" }, {}, 1e6, 10.0);
  EXPECT_TRUE(flood.Overflow);
  EXPECT_LE(flood.Output.size(), 1000000u);
  int polls = 0;
  const HelperProcessResult cancelled =
    RunHelperProcess("/bin/sh", { "-c", "sleep 30" }, {}, 1e8, 0.0, [&polls]() { return ++polls < 3; });
  EXPECT_TRUE(cancelled.Cancelled);
  EXPECT_THROW(RunHelperProcess("/nonexistent/helper", {}, {}, 1e8, 1.0), std::runtime_error);
}

TEST(HelperProcess, ByteReaderNeverReadsPastTheEnd)
{
  const std::vector<char> bytes = { 5, 0, 0, 0, 'a', 'b' };
  ByteReader r(bytes, "test helper");
  EXPECT_THROW(r.String(), std::runtime_error); // says 5 characters, has 2
}

TEST(HelperProcess, PersistentHelperServesFramesAndRestartsAfterACrash)
{
  // A frame server in Python: answers "<count>:<request>", counts requests
  // since it started; "crash" kills it with SIGSEGV, "sleep" hangs.
  const std::string server =
    "import os, signal, struct, sys, time\n"
    "n = 0\n"
    "while True:\n"
    "    h = sys.stdin.buffer.read(8)\n"
    "    if len(h) < 8: sys.exit(0)\n"
    "    data = sys.stdin.buffer.read(struct.unpack('<Q', h)[0])\n"
    "    n += 1\n"
    "    if data == b'crash': os.kill(os.getpid(), signal.SIGSEGV)\n"
    "    if data == b'sleep': time.sleep(30)\n"
    "    out = str(n).encode() + b':' + data\n"
    "    sys.stdout.buffer.write(struct.pack('<Q', len(out)) + out)\n"
    "    sys.stdout.buffer.flush()\n";
  PersistentHelperProcess helper("/usr/bin/python3", { "-c", server });
  const auto request = [&](const std::string& text, std::function<bool()> keepGoing = {}) {
    return helper.Request(std::vector<char>(text.begin(), text.end()), 1e6, 20.0, keepGoing);
  };
  HelperProcessResult a = request("first");
  EXPECT_EQ(a.ExitCode, 0);
  EXPECT_EQ(Text(a), "1:first");
  EXPECT_EQ(Text(request(std::string(300000, 'x'))).size(), 300002u); // larger than a socket buffer
  EXPECT_EQ(Text(request("third")), "3:third");                       // the same process
  const HelperProcessResult crash = request("crash");
  EXPECT_EQ(crash.Signal, 11);
  EXPECT_EQ(Text(request("again")), "1:again"); // restarted
  int polls = 0;
  const HelperProcessResult cancelled = request("sleep", [&polls]() { return ++polls < 3; });
  EXPECT_TRUE(cancelled.Cancelled);
  EXPECT_EQ(Text(request("after")), "1:after");
}
