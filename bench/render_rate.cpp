// In-process render rate: what the service could sustain if HTTP cost nothing. `workers` threads
// (the server's render slots) each loop over the whole inline-request path for `seconds`: parse the
// JSON text, prepare the scene (tessellation, scene id, placement warnings), render with `threads`
// tile threads and encode the PNG, with the BSP and shadow caches a server keeps. Prints and writes
// {renders, seconds, renders_per_s}; bench/service_rate.sh compares it with wrk on POST /v1/render.
//   bench_render_rate --request FILE [--workers 2] [--threads 2] [--seconds 20] [--out FILE]
#include "render/core/timer.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace rr;

int main(int argc, char** argv) {
  std::string request_path, out_path;
  int workers = 2, threads = 2;
  double seconds = 20.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--request") request_path = value;
    else if (flag == "--workers") workers = std::stoi(value);
    else if (flag == "--threads") threads = std::stoi(value);
    else if (flag == "--seconds") seconds = std::stod(value);
    else if (flag == "--out") out_path = value;
    else {
      std::cerr << "unknown flag " << flag << "\n";
      return 2;
    }
  }
  std::ifstream in(request_path, std::ios::binary);
  if (!in) {
    std::cerr << "usage: bench_render_rate --request FILE [--workers N] [--threads N] [--seconds S] [--out FILE]\n";
    return 2;
  }
  std::stringstream text;
  text << in.rdbuf();
  const std::string body = text.str();

  BspCache bsp_cache(256u << 20);
  ShadowCache shadow_cache(256u << 20);
  std::atomic<size_t> renders{0};
  std::atomic<bool> stop{false};
  auto loop = [&] {
    while (!stop.load(std::memory_order_relaxed)) {
      RenderRequest request = parse_request(body);
      const PreparedScene scene = prepare_scene(std::move(request.scene));
      RenderContext context;
      context.bsp_cache = &bsp_cache;
      context.shadow_cache = &shadow_cache;
      context.threads = unsigned(threads);
      const RenderOutcome out = render(request, scene, context);
      if (out.png.empty()) std::abort();
      ++renders;
    }
  };
  Stopwatch clock;
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) pool.emplace_back(loop);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  stop = true;
  for (std::thread& t : pool) t.join();
  const double elapsed = clock.elapsed_ms() / 1000.0;
  nlohmann::ordered_json j{{"request", request_path}, {"workers", workers},
                           {"threads", threads},      {"renders", renders.load()},
                           {"seconds", elapsed},      {"renders_per_s", double(renders.load()) / elapsed}};
  std::cout << j.dump() << "\n";
  if (!out_path.empty()) std::ofstream(out_path) << j.dump(1) << "\n";
  return 0;
}
