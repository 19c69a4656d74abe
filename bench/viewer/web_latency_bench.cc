// The --web stream's latency against issue 30's targets (p50 <= 2 ms, p99 <= 20 ms with 10
// pages at 20 Hz on loopback): the viewer's WebServer on 127.0.0.1:0 and N pages in this
// process (Beast WebSocket clients, one thread each, reading as a browser's socket does),
// frames published at a fixed rate as the viewer's link publishes them (FrameMessageJson of
// the IRB 1600's 8 frames and one probe). Latency: from the publish call (the viewer has
// posed the frame) to a page having read the message. No browser: the page's drawing is not
// in it (docs/performance.md has the browser's figures from WebViewTest).
//
//   web_latency_bench [--pages 10] [--hz 20] [--seconds 20] [--stalled 0]
//
// With --connect HOST:PORT the pages open a running `mbstream-viewer --web` instead (plain
// WebSocket; --token T is sent as the page's token) and read its frames for --seconds: the
// latency from the viewer's own posing, and the VTK window's draws per second as the frames
// report them (render_fps), to compare with and without pages open.
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "viewer/web/frame_message.h"
#include "viewer/web/web_server.h"

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using namespace mbstream::viewer;

double UnixMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

double NumberAfter(const std::string& text, const char* key) {
  const std::size_t at = text.find(key);
  return at == std::string::npos ? -1.0
                                 : std::strtod(text.c_str() + at + std::strlen(key), nullptr);
}

struct PageResult {
  std::vector<double> latency_ms;
  long long missed = 0;
  double render_fps_sum = 0;  // over the frames read
};

struct Target {
  std::string host = "127.0.0.1", port, token;
  long long last = 0;  // read until this frame number (0: until `until`)
  Clock::time_point until = Clock::time_point::max();
};

// One page: sends its token, reads until the target's last frame or time, counting the
// frames it did not get.
void ReadPage(const Target& target, PageResult* result) {
  asio::io_context ioc;
  tcp::resolver resolver(ioc);
  websocket::stream<tcp::socket> ws(ioc);
  asio::connect(ws.next_layer(), resolver.resolve(target.host, target.port));
  ws.next_layer().set_option(tcp::no_delay(true));
  ws.handshake(target.host, "/ws");
  ws.write(asio::buffer("{\"token\":\"" + target.token + "\"}"));
  long long previous = 0;
  beast::flat_buffer buffer;
  for (;;) {
    ws.read(buffer);
    const std::string text = beast::buffers_to_string(buffer.data());
    const double received = UnixMs();
    buffer.consume(buffer.size());
    if (text.find("\"type\":\"denied\"") != std::string::npos) {
      std::fprintf(stderr, "web_latency_bench: refused: %s\n", text.c_str());
      std::exit(1);
    }
    if (text.find("\"type\":\"frame\"") == std::string::npos) continue;
    const auto n = static_cast<long long>(NumberAfter(text, "\"n\":"));
    result->latency_ms.push_back(received - NumberAfter(text, "\"posed_ms\":"));
    result->render_fps_sum += NumberAfter(text, "\"render_fps\":");
    if (previous && n > previous + 1) result->missed += n - previous - 1;
    previous = n;
    if ((target.last && n >= target.last) || Clock::now() >= target.until) break;
  }
  beast::error_code ignored;
  ws.close(websocket::close_code::normal, ignored);
}

struct Percentiles {
  std::vector<double> sorted;
  long long missed = 0;
  double at(double q) const {
    return sorted.empty()
               ? -1.0
               : sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  }
};

Percentiles Gather(const std::vector<PageResult>& results) {
  Percentiles all;
  for (const auto& r : results) {
    all.sorted.insert(all.sorted.end(), r.latency_ms.begin(), r.latency_ms.end());
    all.missed += r.missed;
  }
  std::sort(all.sorted.begin(), all.sorted.end());
  return all;
}

std::vector<PageResult> ReadPages(const Target& target, int pages) {
  std::vector<PageResult> results(static_cast<std::size_t>(pages));
  std::vector<std::thread> readers;
  for (int p = 0; p < pages; ++p) readers.emplace_back(ReadPage, target, &results[p]);
  for (auto& reader : readers) reader.join();
  return results;
}

// --connect: N pages on a running viewer for `seconds`.
int ConnectToViewer(const std::string& address, const std::string& token, int pages,
                    double seconds) {
  Target target;
  target.host = address.substr(0, address.rfind(':'));
  target.port = address.substr(address.rfind(':') + 1);
  target.token = token;
  target.until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(seconds));
  const std::vector<PageResult> results = ReadPages(target, pages);
  const Percentiles all = Gather(results);
  const double fps =
      results[0].latency_ms.empty()
          ? -1.0
          : results[0].render_fps_sum / static_cast<double>(results[0].latency_ms.size());
  std::printf(
      "web_latency_bench: %d pages on the viewer at %s for %.0f s: posed -> read p50 %.3f ms, "
      "p90 %.3f ms, p99 %.3f ms over %zu frames read; %lld missed; the viewer's draws %.1f/s\n",
      pages, address.c_str(), seconds, all.at(0.5), all.at(0.9), all.at(0.99), all.sorted.size(),
      all.missed, fps);
  return 0;
}

// N pages on a WebServer of this process, frames at `hz` for `seconds`.
int ServeInProcess(int pages, int stalled, double hz, double seconds) {
  const long long frames = std::max(1LL, static_cast<long long>(hz * seconds));
  WebOptions options;
  options.address = "127.0.0.1:0";
  options.root = MBSTREAM_WEB_ROOT;
  options.max_pages = pages + stalled + 1;
  WebServer server(std::move(options), nullptr);
  server.Start();
  const std::string url = server.url();
  Target target;
  target.port = url.substr(url.rfind(':') + 1, url.size() - url.rfind(':') - 2);
  target.last = frames;
  server.SetScene(R"({"type":"scene","version":1})");

  std::vector<PageResult> results;
  std::thread readers([&] { results = ReadPages(target, pages); });
  asio::io_context stalled_ioc;  // pages that open and never read
  std::vector<std::unique_ptr<websocket::stream<tcp::socket>>> stalled_pages;
  for (int p = 0; p < stalled; ++p) {
    auto ws = std::make_unique<websocket::stream<tcp::socket>>(stalled_ioc);
    tcp::resolver resolver(stalled_ioc);
    asio::connect(ws->next_layer(), resolver.resolve("127.0.0.1", target.port));
    ws->handshake("127.0.0.1", "/ws");
    stalled_pages.push_back(std::move(ws));
  }
  while (server.pages() < pages + stalled)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));

  // The viewer's frame: the IRB 1600's 8 frame matrices and its TCP probe.
  std::vector<Eigen::Isometry3d> poses(8, Eigen::Isometry3d::Identity());
  std::vector<ProbeReport> probes{{"Tcp", Eigen::Vector3d(0.9, 0.1, 1.2), "World"}};
  mbstream::v1::ViewerStatus status;
  status.set_run_id("r-20261126-230000-bench");
  status.set_state("running");
  status.set_mode("live");
  std::size_t bytes = 0;
  const auto period = std::chrono::duration<double>(1.0 / hz);
  const auto start = Clock::now();
  for (long long n = 1; n <= frames; ++n) {
    std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(period * n));
    for (auto& pose : poses) pose.rotate(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()));
    status.set_seq(n);
    status.set_t_s(static_cast<double>(n) / hz);
    FrameMessage frame;
    frame.scene_version = 1;
    frame.number = static_cast<std::uint64_t>(n);
    frame.posed_unix_ms = UnixMs();
    frame.frames = poses;
    frame.probes = probes;
    std::string json = FrameMessageJson(frame, status);
    bytes = json.size();
    server.PublishFrame(std::move(json));
  }
  readers.join();
  server.Stop();

  const Percentiles all = Gather(results);
  std::printf(
      "web_latency_bench: %d pages (+%d stalled) at %.0f Hz for %.0f s, %zu bytes/frame: "
      "posed -> read p50 %.3f ms, p90 %.3f ms, p99 %.3f ms, max %.3f ms over %zu frames read; "
      "%lld missed; targets p50 <= 2 ms, p99 <= 20 ms: %s\n",
      pages, stalled, hz, seconds, bytes, all.at(0.5), all.at(0.9), all.at(0.99), all.at(1.0),
      all.sorted.size(), all.missed, all.at(0.5) <= 2.0 && all.at(0.99) <= 20.0 ? "met" : "MISSED");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int pages = 10, stalled = 0;
  double hz = 20, seconds = 20;
  std::string connect, token;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const char* value = argv[i + 1];
    if (flag == "--pages") {
      pages = std::atoi(value);
    } else if (flag == "--stalled") {
      stalled = std::atoi(value);
    } else if (flag == "--hz") {
      hz = std::atof(value);
    } else if (flag == "--seconds") {
      seconds = std::atof(value);
    } else if (flag == "--connect") {
      connect = value;
    } else if (flag == "--token") {
      token = value;
    } else {
      std::fprintf(stderr,
                   "usage: web_latency_bench [--pages N] [--hz X] [--seconds S] [--stalled N] "
                   "[--connect HOST:PORT [--token T]]\n");
      return 2;
    }
  }
  if (pages < 1) return 2;
  if (!connect.empty()) return ConnectToViewer(connect, token, pages, seconds);
  return ServeInProcess(pages, stalled, hz, seconds);
}
