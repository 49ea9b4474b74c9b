// Beltrami core: running a third-party parser or mesher in a helper process.
//
// Some libraries we rely on crash on bad input instead of reporting it:
// OpenVDB's parser hangs on truncated files and corrupts the heap on mutated
// ones; TetGen 1.5 (libtet) frees its memory pools twice when it throws on a
// self-intersecting or nearly touching surface.  Such work runs in a small
// helper executable: a crash, a hang or a runaway answer there becomes an
// error message here, never a crash of ParaView.  Linux/POSIX only.
#pragma once

#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace beltrami
{

struct HelperProcessResult
{
  std::vector<char> Output; ///< what the helper wrote to its standard output
  int ExitCode = -1;        ///< when it exited normally
  int Signal = 0;           ///< non-zero: it was killed by this signal (a crash)
  bool TimedOut = false;    ///< killed after the timeout
  bool Overflow = false;    ///< killed: it wrote more than the maximum
  bool Cancelled = false;   ///< killed: keepGoing() returned false
};

/// Runs `program` with `arguments`, `input` as its standard input (held in
/// an anonymous memory file: no pipe to block on, no SIGPIPE) and its
/// standard output collected, at most maximumBytes.  timeout (seconds, <= 0:
/// none) and keepGoing (polled every 0.2 s; may be empty) kill it early.
/// Throws std::runtime_error when it cannot be started.
HelperProcessResult RunHelperProcess(const std::string& program, const std::vector<std::string>& arguments,
  const std::vector<char>& input, double maximumBytes, double timeout,
  const std::function<bool()>& keepGoing = {});

/// A helper process kept running between requests, so that the memory it
/// faulted in stays warm (on machines where page faults are slow a fresh process pays ~1 ms per
/// MiB it touches).  Its standard input and output are one end of a socket
/// pair; a request and its answer are frames: a uint64 length and the bytes.
/// The helper is started by the first request and again after it died: a
/// crash answers the request it was working on with Signal set, a cancel
/// or timeout kills it.  Requests are serialized.  The helper exits when
/// its input closes (this object destroyed, or this process gone).
class PersistentHelperProcess
{
public:
  PersistentHelperProcess(std::string program, std::vector<std::string> arguments);
  ~PersistentHelperProcess();
  PersistentHelperProcess(const PersistentHelperProcess&) = delete;
  PersistentHelperProcess& operator=(const PersistentHelperProcess&) = delete;

  /// Sends `request`, returns the answer in Output (ExitCode 0: the helper
  /// is still running).  Throws std::runtime_error when it cannot start.
  HelperProcessResult Request(const std::vector<char>& request, double maximumBytes, double timeout,
    const std::function<bool()>& keepGoing = {});

private:
  void Stop(HelperProcessResult& result, bool kill);

  std::string Program;
  std::vector<std::string> Arguments;
  std::mutex Mutex;
  int Pid = -1;
  int Socket = -1;
};

/// The helper `name` in the directory of the shared library that holds
/// `symbol` (where the build puts it), or the value of the environment
/// variable `overrideVariable` when set.
std::string HelperPathNextTo(const void* symbol, const std::string& name, const char* overrideVariable);

/// Reads the little-endian binary answers of the helpers and never past
/// their end (throws std::runtime_error with `what` in the message).
class ByteReader
{
public:
  ByteReader(const std::vector<char>& bytes, std::string what)
    : Bytes(bytes)
    , What(std::move(what))
  {
  }
  template <typename T>
  T Get()
  {
    T v;
    this->Take(&v, sizeof(T));
    return v;
  }
  std::string String(); ///< a uint32 length and the characters
  void Take(void* out, std::size_t n);
  std::size_t Left() const { return this->Bytes.size() - this->Position; }
  std::size_t Offset() const { return this->Position; }

private:
  const std::vector<char>& Bytes;
  std::string What;
  std::size_t Position = 0;
};

} // namespace beltrami
