// Rendering costs per frame for the example characters: draw-list rebuild (fill mesh
// positions + stroke tessellation) and a software-rendered 512x512 frame.
#include "character/load.h"
#include "render/canvas.h"

#include <benchmark/benchmark.h>

namespace {

const char* kNames[] = {"butterfly", "figure", "koi"};

mar::Character load(int i) {
  auto r = mar::load_character(std::string(MARIONETTE_SOURCE_DIR) + "/config/characters/" + kNames[i] + ".svg");
  if (!r.ok()) std::abort();
  return *r.value;
}

void BM_build_draw_list(benchmark::State& st) {
  const mar::Character ch = load(static_cast<int>(st.range(0)));
  const mar::CharacterMesh mesh = mar::prepare_mesh(ch);
  mar::DrawList list;
  for (auto _ : st) {
    list.clear();
    mar::build_draw_list(ch, mesh, {}, mar::fit_view(ch.width, ch.height, 512, 512), 0.25, list);
    benchmark::DoNotOptimize(list.indices.data());
  }
  st.SetLabel(kNames[st.range(0)]);
  st.counters["vertices"] = static_cast<double>(ch.vertex_count());
  st.counters["triangles"] = static_cast<double>(list.indices.size() / 3);
}
BENCHMARK(BM_build_draw_list)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

void BM_prepare_mesh(benchmark::State& st) {
  const mar::Character ch = load(static_cast<int>(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(mar::prepare_mesh(ch));
  st.SetLabel(kNames[st.range(0)]);
}
BENCHMARK(BM_prepare_mesh)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

void BM_software_frame_512(benchmark::State& st) {
  const mar::Character ch = load(static_cast<int>(st.range(0)));
  const mar::CharacterMesh mesh = mar::prepare_mesh(ch);
  auto canvas = mar::Canvas::offscreen(512, 512);
  mar::DrawList list;
  for (auto _ : st) {
    (*canvas.value)->clear(mar::Rgba{1, 1, 1, 1});
    list.clear();
    mar::build_draw_list(ch, mesh, {}, mar::fit_view(ch.width, ch.height, 512, 512), 0.25, list);
    (*canvas.value)->draw(list);
  }
  st.SetLabel(kNames[st.range(0)]);
}
BENCHMARK(BM_software_frame_512)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
