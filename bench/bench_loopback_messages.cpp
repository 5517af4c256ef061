// What one message costs the CPU on this machine, below any DDS: the floor under the ROS 2
// bridge's share of a live run (docs/ROS2.md, "The bridge's CPU"). Each operation is paced
// at RATE per second (default 40, a fast laser), so that the other side really sleeps in
// between, as in a live run; the costs are thread CPU times (CLOCK_THREAD_CPUTIME_ID) per
// operation, min and median over REPEATS rounds of COUNT operations:
//   udp send, receiver waiting      sendto() of a 100-byte datagram over 127.0.0.1 to a thread
//                                   blocked in recv(): the sender's CPU (the kernel delivers
//                                   the datagram and wakes the receiver on the sender's time)
//   udp receive, woken              the receiving thread's CPU per datagram, its sleep and
//                                   wake-up included
//   udp send, nobody waiting        the same datagram into a socket nobody waits on (drained
//                                   later): delivery without a wake-up
//   condition variable wake         notify_one() to a thread blocked in wait(): the notifier's
//                                   CPU (what a receive thread pays to hand a scan over)
// Usage: bench_loopback_messages [COUNT (default 400)] [RATE (default 40)] [REPEATS (default 5)]
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

double threadCpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Loopback {
  int rx = -1, tx = -1;
  sockaddr_in to{};
  Loopback() {
    rx = socket(AF_INET, SOCK_DGRAM, 0);
    tx = socket(AF_INET, SOCK_DGRAM, 0);
    if (rx < 0 || tx < 0) throw std::runtime_error("socket() failed");
    to.sin_family = AF_INET;
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (bind(rx, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0)
      throw std::runtime_error("bind() to 127.0.0.1 failed");
    socklen_t len = sizeof to;
    getsockname(rx, reinterpret_cast<sockaddr*>(&to), &len);
  }
  ~Loopback() {
    close(rx);
    close(tx);
  }
  void send() const {
    static const char msg[100] = {};
    if (sendto(tx, msg, sizeof msg, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) != sizeof msg)
      throw std::runtime_error("sendto() failed");
  }
};

struct Costs {
  double send_waiting = 0, receive_woken = 0, send_unwaited = 0, notify = 0;  // seconds per op
};

void pace(int rate) { std::this_thread::sleep_for(std::chrono::microseconds(1000000 / rate)); }

Costs round(int count, int rate) {
  Costs c;
  {  // a receiver blocked in recv()
    Loopback l;
    double rx_cpu = 0;
    std::thread rx([&] {
      char buf[2048];
      const double t0 = threadCpu();
      for (int i = 0; i < count; ++i) recv(l.rx, buf, sizeof buf, 0);
      rx_cpu = threadCpu() - t0;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    double tx_cpu = 0;
    for (int i = 0; i < count; ++i) {
      const double t0 = threadCpu();
      l.send();
      tx_cpu += threadCpu() - t0;
      pace(rate);
    }
    rx.join();
    c.send_waiting = tx_cpu / count;
    c.receive_woken = rx_cpu / count;
  }
  {  // nobody waiting: a few datagrams at a time, then drained
    Loopback l;
    double tx_cpu = 0;
    char buf[2048];
    for (int i = 0; i < count; ++i) {
      const double t0 = threadCpu();
      l.send();
      tx_cpu += threadCpu() - t0;
      if (i % 8 == 7)
        for (int k = 0; k < 8; ++k) recv(l.rx, buf, sizeof buf, 0);
      pace(rate);
    }
    c.send_unwaited = tx_cpu / count;
  }
  {  // a thread blocked on a condition variable, handed one item at a time
    std::mutex mu;
    std::condition_variable cv;
    int ready = 0, taken = 0;
    std::thread waiter([&] {
      std::unique_lock<std::mutex> lock(mu);
      while (taken < count) {
        cv.wait(lock, [&] { return ready > taken; });
        ++taken;
      }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    double cpu = 0;
    for (int i = 0; i < count; ++i) {
      const double t0 = threadCpu();
      {
        std::lock_guard<std::mutex> lock(mu);
        ++ready;
      }
      cv.notify_one();
      cpu += threadCpu() - t0;
      pace(rate);
    }
    waiter.join();
    c.notify = cpu / count;
  }
  return c;
}

void row(const char* name, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::printf("%-32s %8.1f %8.1f\n", name, 1e6 * v.front(), 1e6 * v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 400;
  const int rate = argc > 2 ? std::atoi(argv[2]) : 40;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 5;
  if (count < 8 || rate < 1 || rate > 100000 || repeats < 1) {
    std::fprintf(stderr, "usage: bench_loopback_messages [COUNT >= 8] [RATE 1..100000] [REPEATS >= 1]\n");
    return 2;
  }
  std::vector<double> sw, rw, su, nt;
  try {
    for (int r = 0; r < repeats; ++r) {
      const Costs c = round(count, rate);
      sw.push_back(c.send_waiting);
      rw.push_back(c.receive_woken);
      su.push_back(c.send_unwaited);
      nt.push_back(c.notify);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_loopback_messages: %s\n", e.what());
    return 1;
  }
  std::printf("%d rounds of %d operations at %d per second; thread CPU per operation [us]\n",
              repeats, count, rate);
  std::printf("%-32s %8s %8s\n", "operation", "min", "median");
  row("udp send, receiver waiting", sw);
  row("udp receive, woken", rw);
  row("udp send, nobody waiting", su);
  row("condition variable wake", nt);
  return 0;
}
