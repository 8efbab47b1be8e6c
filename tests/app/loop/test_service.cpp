// The systemd notify protocol against a test's own notify socket: READY=1 after the first frame, then
// WATCHDOG=1 at half the interval while frames come, none while the frame loop is stalled; and
// `marionette run` under a notify socket says READY.
#include "app/loop/service.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace mar {
namespace {

// A unix datagram socket listening where systemd's notify socket would be.
struct NotifyListener {
  int fd = -1;
  std::string path;
  NotifyListener() {
    path = (test::temp_dir("notify") / "sock").string();
    ::unlink(path.c_str());
    fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    path.copy(a.sun_path, sizeof a.sun_path - 1);
    EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    timeval tv{0, 1000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~NotifyListener() {
    ::close(fd);
    ::unlink(path.c_str());
  }
  // Every message received so far.
  std::vector<std::string> take() {
    std::vector<std::string> out;
    char buf[512];
    for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) out.emplace_back(buf, size_t(n));
    return out;
  }
};

int count(const std::vector<std::string>& msgs, const std::string& what) {
  int n = 0;
  for (const std::string& m : msgs) n += m.find(what) != std::string::npos;
  return n;
}

TEST(ServiceNotifier, ReadyThenWatchdogWhileFramesComeAndNoneWhenStalled) {
  NotifyListener listener;
  ::setenv("NOTIFY_SOCKET", listener.path.c_str(), 1);
  ::setenv("WATCHDOG_USEC", "100000", 1);  // 0.1 s: a ping every 50 ms
  ::unsetenv("WATCHDOG_PID");
  {
    ServiceNotifier s;
    ASSERT_TRUE(s.active());
    EXPECT_EQ(s.watchdog_usec(), 100000u);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_TRUE(listener.take().empty());  // no frame yet: not ready
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(600);
    while (std::chrono::steady_clock::now() < until) {  // frames at 200 Hz
      s.frame_presented();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const auto live = listener.take();
    ASSERT_FALSE(live.empty());
    EXPECT_NE(live.front().find("READY=1"), std::string::npos) << live.front();
    EXPECT_GE(count(live, "WATCHDOG=1"), 2);  // ~11 expected; a busy machine may delay the thread
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the last ping of the live part
    listener.take();
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // stalled: no frames
    EXPECT_EQ(count(listener.take(), "WATCHDOG=1"), 0);
    s.frame_presented();  // frames again: pings again
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    s.frame_presented();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_GE(count(listener.take(), "WATCHDOG=1"), 1);
  }
  EXPECT_EQ(count(listener.take(), "STOPPING=1"), 1);
  ::unsetenv("NOTIFY_SOCKET");
  ::unsetenv("WATCHDOG_USEC");
  ServiceNotifier outside;  // no service manager: nothing runs
  EXPECT_FALSE(outside.active());
}

TEST(ServiceNotifier, TheShowSaysReadyUnderANotifySocket) {
  NotifyListener listener;
  const auto r = test::run_cli("run '" + (test::source_dir() / "config/shows/demo.toml").string() +
                               "' --headless --frames 30",
                               "NOTIFY_SOCKET=" + listener.path + " WATCHDOG_USEC=2000000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto msgs = listener.take();
  EXPECT_EQ(count(msgs, "READY=1"), 1);
  EXPECT_EQ(count(msgs, "STOPPING=1"), 1);
}

}  // namespace
}  // namespace mar
