// The plan of a fused scene: where each creature's points sit, the order the link
// pass computes the links in (arrange_links, order_by_need), the impulse slots that
// give each mass its impulses in its model's file order, the muscle targets' groups
// of shared sines, and the lane tables of the frame in registers.
//
// Everything here is decided once, when the scene is built; nothing here changes
// a bit of the result (why each freedom is exact is said where it is taken).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "core/detail/bits.hpp"
#include "core/fused/scene_data.hpp"

namespace soda::fused {

namespace {

/// `values` (one per natural index) rearranged so that block b of W holds item
/// b + kLaneLink(W, l) in lane l; padded with `fill` to `padded` entries.
AVec<double> in_lane_order(const std::vector<double>& values, int w, std::size_t padded, double fill) {
  AVec<double> out(padded, fill);
  for (std::size_t b = 0; b < padded; b += static_cast<std::size_t>(w)) {
    for (int l = 0; l < w; ++l) {
      const std::size_t item = b + static_cast<std::size_t>(kLaneLink(w, l));
      if (item < values.size()) out[b + static_cast<std::size_t>(l)] = values[item];
    }
  }
  return out;
}

} // namespace

void SceneData::build(const std::vector<const Model*>& models, long long budget, FastStepOptions opt) {
  options = opt;
  simd = opt.simd == SimdLevel::Auto ? best_simd_level() : opt.simd;
  if (!simd_level_supported(simd)) simd = best_simd_level();
  W = width_of(simd);
  sine_fn = opt.vector_sines ? exact_sin_fn(simd) : &scalar_sines;
  place_points(models, budget);
  set_mass_parameters();
  std::vector<ActingLink> acting = order_links();
  const std::vector<std::vector<std::int32_t>> impulses_of_mass = place_links(acting);
  const std::vector<int> slot_of_link = lane_slot_of_link();
  place_link_ends_in_lanes(slot_of_link);
  set_link_parameters(acting, slot_of_link);
  prepare_sine_rows();
  place_bars();
  plan_register_frame(acting, slot_of_link, impulses_of_mass);
}

// The creatures' points in working order, and the arrays that hold them.
void SceneData::place_points(const std::vector<const Model*>& models, long long budget) {
  creatures.assign(models.size(), {});
  masses = 0;
  fixed_points = 0;
  for (std::size_t c = 0; c < models.size(); ++c) {
    Creature& cr = creatures[c];
    cr.model = models[c];
    cr.needs = analyse_scene(*models[c], budget);
    cr.mass_base = masses;
    masses += models[c]->mass_count;
    any_wave = any_wave || cr.needs.wave;
    any_gravity = any_gravity || cr.needs.gravity;
    bars = std::max(bars, cr.needs.bars);
  }
  padded_masses = (masses + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  // A creature's masses get working indices [mass_base, mass_base + mass_count)
  // in order of decreasing degree (acting links), so that the impulse sums go
  // over consecutive masses of similar degree (mass_kernel: few padding
  // rounds, sums kept in registers for the mass step). The file order stays in
  // work_of_point for what runs in mass order.
  for (Creature& cr : creatures) {
    const Model& m = *cr.model;
    std::vector<int> degree(static_cast<std::size_t>(m.mass_count), 0);
    for (int i = 0; i < m.link_count(); ++i) {
      if (m.is_mass(m.link_a[i])) ++degree[m.link_a[i]];
      if (m.is_mass(m.link_b[i])) ++degree[m.link_b[i]];
    }
    std::vector<int> order(static_cast<std::size_t>(m.mass_count));
    for (int p = 0; p < m.mass_count; ++p) order[p] = p;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return degree[a] > degree[b]; });
    cr.work_of_point.resize(static_cast<std::size_t>(m.point_count));
    for (int r = 0; r < m.mass_count; ++r) cr.work_of_point[order[r]] = cr.mass_base + r;
    for (int p = m.mass_count; p < m.point_count; ++p) cr.work_of_point[p] = padded_masses + fixed_points + (p - m.mass_count);
    fixed_points += m.point_count - m.mass_count;
  }
  spare_point = padded_masses + fixed_points;
  // (Avx512Ops::load_points reads kRegisterPoints points whatever the scene's size.)
  positions.assign(2 * static_cast<std::size_t>(std::max(spare_point + 1, Avx512Ops::kRegisterPoints)), 0.0);
  velocities.assign(2 * static_cast<std::size_t>(spare_point + 1), 0.0);
  side_hit.assign(2 * static_cast<std::size_t>(padded_masses), 0.0);
}

// Each mass's own creature's world, in lane order (padding masses: gravity +0,
// so they stay at rest).
void SceneData::set_mass_parameters() {
  std::vector<double> gd, keep, width, height, fs, rs;
  for (const Creature& cr : creatures) {
    const Model& m = *cr.model;
    for (int i = 0; i < m.mass_count; ++i) {
      gd.push_back(m.gravity_step);
      keep.push_back(m.air_keep);
      width.push_back(m.width);
      height.push_back(m.height);
      fs.push_back(m.surface_friction);
      rs.push_back(m.surface_reflection);
    }
  }
  const auto np = static_cast<std::size_t>(padded_masses);
  mass_gravity_step = in_lane_order(gd, W, np, 0.0);
  mass_air_keep = in_lane_order(keep, W, np, 1.0);
  mass_width = in_lane_order(width, W, np, 1.0);
  mass_height = in_lane_order(height, W, np, 1.0);
  mass_surface_friction = in_lane_order(fs, W, np, 1.0);
  mass_surface_reflection = in_lane_order(rs, W, np, 1.0);
}

// The links that can act (a free end) in the order the link pass computes them:
// the wave muscles of every creature first, then the other links, each creature's
// in file order, then arranged in blocks (arrange_links, order_by_need). The order
// links are computed in is free: only the order of the additions into each
// velocity matters, and the impulse slots (place_links) keep each model's file
// order for that.
std::vector<SceneData::ActingLink> SceneData::order_links() {
  std::vector<ActingLink> acting;
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t c = 0; c < creatures.size(); ++c) {
      const Model& m = *creatures[c].model;
      for (int i = 0; i < m.link_count(); ++i) {
        if (!m.is_mass(m.link_a[i]) && !m.is_mass(m.link_b[i])) continue; // no effect at all
        if (is_wave_muscle(m, i) == (pass == 0)) acting.push_back({static_cast<int>(c), i, false, pass == 0, 0});
      }
    }
    if (pass == 0) wave_muscles = static_cast<int>(acting.size());
  }
  arrange_links(acting); // sets padded_wave_muscles
  if (frames_fit_registers(static_cast<int>(acting.size()))) order_by_need(acting);
  return acting;
}

// The link slots' ends, and per mass the impulse slots it adds, in file order of
// its model's links (returned: the impulse pairs of each working mass).
std::vector<std::vector<std::int32_t>> SceneData::place_links(const std::vector<ActingLink>& acting) {
  link_slots = static_cast<int>(acting.size());
  padded_link_slots = (link_slots + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  end_a_offset.assign(static_cast<std::size_t>(padded_link_slots), 0);
  end_b_offset.assign(static_cast<std::size_t>(padded_link_slots), 0);
  link_target.assign(static_cast<std::size_t>(padded_link_slots), 0.0);
  link_springyness.assign(static_cast<std::size_t>(padded_link_slots), 0.0);
  link_swap_sign.assign(static_cast<std::size_t>(padded_link_slots), 1.0);
  impulses.assign(4 * static_cast<std::size_t>(padded_link_slots) + 2, -0.0);
  // Per mass, its impulse pairs in file order of its model's links.
  std::vector<std::vector<std::pair<int, std::int32_t>>> per_mass_file(static_cast<std::size_t>(padded_masses));
  for (int k = 0; k < link_slots; ++k) {
    if (acting[k].creature < 0) {
      end_a_offset[k] = end_b_offset[k] = 2 * static_cast<std::uint32_t>(acting[k].dummy);
      continue;
    }
    const Creature& cr = creatures[acting[k].creature];
    const Model& m = *cr.model;
    const int i = acting[k].link;
    const int a = acting[k].swapped ? m.link_b[i] : m.link_a[i];
    const int b = acting[k].swapped ? m.link_a[i] : m.link_b[i];
    end_a_offset[k] = 2 * static_cast<std::uint32_t>(cr.work_of_point[a]);
    end_b_offset[k] = 2 * static_cast<std::uint32_t>(cr.work_of_point[b]);
    // The pass's end A gets +c*d and end B -c*d, d the file's difference b - a
    // (link_swap_sign): with the ends swapped, the file's end a (the pass's B) takes
    // the +c*d pair and b the -c*d one.
    const bool swapped = acting[k].swapped;
    if (m.is_mass(a)) per_mass_file[cr.work_of_point[a]].emplace_back(i, swapped ? padded_link_slots + k : k);
    if (m.is_mass(b)) per_mass_file[cr.work_of_point[b]].emplace_back(i, swapped ? k : padded_link_slots + k);
  }
  std::vector<std::vector<std::int32_t>> per_mass(static_cast<std::size_t>(padded_masses));
  for (int w = 0; w < padded_masses; ++w) {
    auto& list = per_mass_file[w];
    std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& e : list) per_mass[w].push_back(e.second);
  }
  identity_impulse = 2 * padded_link_slots;
  group_rounds.clear();
  impulse_slots.clear();
  first_slot_of_mass.assign(static_cast<std::size_t>(padded_masses), 0);
  rounds_of_mass.assign(static_cast<std::size_t>(padded_masses), 0);
  for (int g = 0; g < padded_masses; g += kGatherGroup) {
    std::size_t rounds = 0;
    for (int l = 0; l < kGatherGroup; ++l) rounds = std::max(rounds, per_mass[g + l].size());
    group_rounds.push_back(static_cast<std::int32_t>(rounds));
    for (int l = 0; l < kGatherGroup; ++l) {
      first_slot_of_mass[g + l] = static_cast<std::int32_t>(impulse_slots.size()) + l;
      rounds_of_mass[g + l] = static_cast<std::int32_t>(rounds);
    }
    for (std::size_t r = 0; r < rounds; ++r) {
      for (int l = 0; l < kGatherGroup; ++l) {
        const auto& list = per_mass[g + l];
        impulse_slots.push_back(2 * static_cast<std::uint32_t>(r < list.size() ? list[r] : identity_impulse));
      }
    }
  }
  return per_mass;
}

// Targets and springyness in lane order: lane l of block b holds link b*W + kLaneLink(W, l).
std::vector<int> SceneData::lane_slot_of_link() const {
  std::vector<int> slot_of_link(static_cast<std::size_t>(padded_link_slots));
  for (int b = 0; b < padded_link_slots; b += W) {
    for (int l = 0; l < W; ++l) slot_of_link[b + kLaneLink(W, l)] = b + l;
  }
  return slot_of_link;
}

// The link pass with every point in registers (AVX-512, small scenes): each
// end's point in lane order.
void SceneData::place_link_ends_in_lanes(const std::vector<int>& slot_of_link) {
  points_in_registers = simd == SimdLevel::Avx512 && padded_masses + fixed_points <= Avx512Ops::kRegisterPoints;
  end_a_point.clear();
  end_b_point.clear();
  if (points_in_registers) {
    end_a_point.assign(static_cast<std::size_t>(padded_link_slots), 0);
    end_b_point.assign(static_cast<std::size_t>(padded_link_slots), 0);
    for (int k = 0; k < padded_link_slots; ++k) {
      end_a_point[slot_of_link[k]] = end_a_offset[k] / 2;
      end_b_point[slot_of_link[k]] = end_b_offset[k] / 2;
    }
  }
}

// Per link slot its target, springyness and direction; per wave muscle its rest
// length, power and group of shared sine (a distinct phase of its creature).
void SceneData::set_link_parameters(const std::vector<ActingLink>& acting, const std::vector<int>& slot_of_link) {
  muscle_rest.assign(static_cast<std::size_t>(padded_wave_muscles), 0.0);
  muscle_power.assign(static_cast<std::size_t>(padded_wave_muscles), 0.0);
  muscle_group.assign(static_cast<std::size_t>(padded_wave_muscles), 0);
  // Distinct phases per creature (its sines depend on its own wave phase).
  std::vector<std::map<std::uint64_t, int>> group_of_phase(creatures.size());
  for (int k = 0; k < padded_wave_muscles; ++k) {
    if (!acting[k].wave) continue;
    Creature& cr = creatures[acting[k].creature];
    const double phase = cr.model->link_phase[acting[k].link];
    if (group_of_phase[acting[k].creature].try_emplace(bits_of(phase), 0).second) ++cr.groups;
  }
  groups = 0;
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    creatures[c].group_base = groups; // its groups numbered in order of first use below
    groups += creatures[c].groups;
    group_of_phase[c].clear();
  }
  group_phase.assign(static_cast<std::size_t>(groups), 0.0);
  std::vector<int> next_group(creatures.size(), 0);
  for (int k = 0; k < link_slots; ++k) {
    if (acting[k].creature < 0) continue; // dummy: target 0, springyness 0
    const Creature& cr = creatures[acting[k].creature];
    const Model& m = *cr.model;
    const int i = acting[k].link;
    const int q = slot_of_link[k];
    link_target[q] = m.link_rest[i]; // springs, and muscles of power 0: rest*(1 +- 0) = rest
    link_springyness[q] = m.springyness;
    link_swap_sign[q] = acting[k].swapped ? -1.0 : 1.0;
    if (q < padded_wave_muscles) muscle_rest[q] = m.link_rest[i];
    if (!acting[k].wave) continue;
    muscle_power[q] = m.link_power[i];
    auto [it, inserted] = group_of_phase[acting[k].creature].try_emplace(bits_of(m.link_phase[i]), 0);
    if (inserted) {
      it->second = cr.group_base + next_group[acting[k].creature]++;
      group_phase[it->second] = m.link_phase[i];
    }
    muscle_group[q] = it->second;
  }
}

// The rows of sines (sine_rows.hpp): their sizes, and the numbering of the
// distinct sine arguments, made at the first fill.
void SceneData::prepare_sine_rows() {
  // Rows of sines per batch: enough frames that the batch overhead is shared.
  constexpr int kSinesPerBatch = 1024;
  rows_per_fill = std::clamp(kSinesPerBatch / std::max(groups, 1), 1, 16);
  const std::size_t row_values = static_cast<std::size_t>((rows_per_fill * groups + kMaxWidth - 1) / kMaxWidth * kMaxWidth);
  wave_creatures.clear();
  still_creatures.clear();
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    (creatures[c].groups > 0 ? wave_creatures : still_creatures).push_back(static_cast<int>(c));
  }
  row_phase.assign(creatures.size() * static_cast<std::size_t>(rows_per_fill + 1), 0.0);
  sines_in_registers = simd == SimdLevel::Avx512 && groups <= Avx512Ops::kRegisterPoints;
  muscle_group_lane.assign(static_cast<std::size_t>(padded_wave_muscles), 0);
  for (int q = 0; q < padded_wave_muscles; ++q) muscle_group_lane[q] = muscle_group[q];
  arguments.assign(row_values + kMaxWidth, 1.0); // padding lanes: an argument the tables take (args_kernel)
  // Any row of sines by group loads as two registers (sines_in_registers).
  argument_sines.assign(row_values + Avx512Ops::kRegisterPoints, 0.0);
  group_sines.assign(row_values + Avx512Ops::kRegisterPoints, 0.0);
  muscle_argument.assign(static_cast<std::size_t>(padded_wave_muscles), 0);
  muscle_argument_lane.assign(static_cast<std::size_t>(padded_wave_muscles), 0);
  sine_rows = argument_sines.data();
  sine_stride = groups;
  sine_index = muscle_group.data();
  sine_lane = muscle_group_lane.data();
  std::map<std::uint64_t, int> u_of_phase;
  muscle_phase_of_group.assign(static_cast<std::size_t>(groups), 0);
  for (int g = 0; g < groups; ++g) {
    muscle_phase_of_group[g] = u_of_phase.try_emplace(bits_of(group_phase[g]), static_cast<int>(u_of_phase.size())).first->second;
  }
  muscle_phases = static_cast<int>(u_of_phase.size());
  wave_states = 0;
  numbering_valid = false;
  rows_synced = false;
  wave_state_of.assign(creatures.size(), 0);
  wave_state_leader.assign(creatures.size(), 0);
  argument_of_key.assign(creatures.size() * static_cast<std::size_t>(muscle_phases), -1);
  key_of_argument.assign(static_cast<std::size_t>(groups), 0);
  first_argument_of_state.assign(creatures.size() + 1, 0);
  argument_muscle_phase.assign(static_cast<std::size_t>(groups + kMaxWidth), 0.0); // padded for args_kernel
  argument_of_group.assign(static_cast<std::size_t>(groups), 0);
}

// Fixed bars: which creatures have them, the scene mass index of each working
// mass, and the tiles the masses start with.
void SceneData::place_bars() {
  bar_creatures.clear();
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    if (!creatures[c].model->fixed_bars.empty()) bar_creatures.push_back(static_cast<int>(c));
  }
  if (bar_creatures.empty()) return;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const std::size_t words = (static_cast<std::size_t>(masses) + 63) / 64;
  bar_held.assign(words, 0);
  bar_due.assign(words, 0);
  bar_scene_mask.assign(words, 0);
  file_of_work.assign(static_cast<std::size_t>(masses), 0);
  creature_of_mass.assign(static_cast<std::size_t>(masses), 0);
  // A tile's x range, then its box: a mass of a creature with bars starts with no
  // tile (an empty x range: due at first); the others and the padding keep an
  // endless tile with an empty box (never due; bar_scene_mask leaves them out anyway).
  mass_tile.assign(kTileValues * static_cast<std::size_t>(padded_masses), 0.0);
  auto set_tile = [&](int i, const double (&tile)[kTileValues]) {
    for (int v = 0; v < kTileValues; ++v) mass_tile[tile_at(i) + static_cast<std::size_t>(v * W)] = tile[v];
  };
  for (int i = 0; i < padded_masses; ++i) set_tile(i, {-inf, inf, inf, -inf, inf, -inf});
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    Creature& cr = creatures[c];
    const Model& m = *cr.model;
    cr.bar_surface = Surface{m.surface_friction, m.surface_reflection, m.width, m.height};
    const bool with_bars = !cr.model->fixed_bars.empty();
    for (int p = 0; p < cr.model->mass_count; ++p) {
      const int i = cr.work_of_point[static_cast<std::size_t>(p)];
      const int g = cr.mass_base + p;
      file_of_work[static_cast<std::size_t>(i)] = g;
      creature_of_mass[static_cast<std::size_t>(g)] = static_cast<int>(c);
      if (!with_bars) continue;
      bar_scene_mask[static_cast<std::size_t>(g / 64)] |= std::uint64_t{1} << (g % 64);
      set_tile(i, {inf, -inf, inf, -inf, inf, -inf});
    }
  }
  bar_touch.assign(static_cast<std::size_t>(padded_masses / W), 0);
}

// The frame in registers: the register lane of working point (or link slot) p.
void SceneData::plan_register_frame(const std::vector<ActingLink>& acting, const std::vector<int>& slot_of_link,
                                    const std::vector<std::vector<std::int32_t>>& per_mass) {
  frame_in_registers = frames_fit_registers(padded_link_slots);
  reg_end_a_lane.clear();
  reg_end_b_lane.clear();
  reg_impulse_lane.clear();
  reg_impulse_sign.clear();
  reg_upper_blocks.clear();
  reg_has_impulse.clear();
  reg_rounds.clear();
  reg_real_links.clear();
  if (frame_in_registers) {
    const auto lane_of = [](int p) {
      const int j = p % kMaxWidth;
      return p - j + (j < kMaxWidth / 2 ? 2 * j : 2 * (j - kMaxWidth / 2) + 1); // kLaneLink inverted
    };
    reg_real_links.assign(static_cast<std::size_t>(padded_link_slots / kMaxWidth), 0);
    for (int k = 0; k < link_slots; ++k) {
      if (acting[k].creature >= 0) reg_real_links[k / kMaxWidth] |= static_cast<std::uint8_t>(1u << (slot_of_link[k] % kMaxWidth));
    }
    reg_end_a_lane.assign(static_cast<std::size_t>(padded_link_slots), 0);
    reg_end_b_lane.assign(static_cast<std::size_t>(padded_link_slots), 0);
    for (int k = 0; k < padded_link_slots; ++k) {
      reg_end_a_lane[slot_of_link[k]] = lane_of(static_cast<int>(end_a_offset[k] / 2));
      reg_end_b_lane[slot_of_link[k]] = lane_of(static_cast<int>(end_b_offset[k] / 2));
    }
    for (int blk = 0; blk < padded_masses / kMaxWidth; ++blk) {
      std::size_t rounds = 0;
      for (int l = 0; l < kMaxWidth; ++l) rounds = std::max(rounds, per_mass[blk * kMaxWidth + kLaneLink(kMaxWidth, l)].size());
      reg_rounds.push_back(static_cast<int>(rounds));
      for (std::size_t r = 0; r < rounds; ++r) {
        std::uint8_t upper = 0, valid = 0;
        for (int l = 0; l < kMaxWidth; ++l) {
          const auto& list = per_mass[blk * kMaxWidth + kLaneLink(kMaxWidth, l)];
          const bool b_end = r < list.size() && list[r] >= padded_link_slots;
          const int lane = r < list.size() ? lane_of(b_end ? list[r] - padded_link_slots : list[r]) : 0;
          reg_impulse_lane.push_back(lane % (2 * kMaxWidth));
          reg_impulse_sign.push_back(b_end || r >= list.size() ? -0.0 : 0.0); // no impulse: +0.0 ^ sign = -0.0
          if (lane >= 2 * kMaxWidth) upper = static_cast<std::uint8_t>(upper | (1u << l));
          if (r < list.size()) valid = static_cast<std::uint8_t>(valid | (1u << l));
        }
        reg_upper_blocks.push_back(upper);
        reg_has_impulse.push_back(valid);
      }
    }
  }
}

// The order the link pass computes links in is free (only the order of the
// additions into each velocity matters, and the impulse_slots keep each model's file
// order for that), and so is which end is A: with the ends swapped the pass
// still forms the file's difference d = b - a (link_swap_sign: not the pass's b - a
// negated, which is -0 where the file's is +0), so the length, the factor c and
// c*d are the same bits, and the impulse_slots give the file's end a +c*d and b -c*d.
// So blocks of W links are formed whose A ends are the W masses of one block of
// masses, in slot order: the link pass then loads those ends as two whole
// vectors instead of W pair loads with their offsets (bench/README.md, "Design
// figures": link blocks).
// A block may take one dummy lane (W = 8) where a mass has no link left.
// Layout: the wave muscles first, formed blocks then the others, filled up to a
// multiple of kMaxWidth with other links (target slots [0, padded_wave_muscles) are the ones
// that change per frame); then the other links, formed blocks first.
// The frame in registers (register_chunk) computes its link blocks in order, one
// square root per block a few cycles after the other, and a mass adds its
// impulses in rounds, one round per link in file order. A link whose impulse is
// added early in a long list holds up more additions after it than one added last,
// so the links are ordered by how many rounds still follow their first use (the
// most first) within the wave impulse_slots and within the others; a round that takes no
// impulse of the last block then does not wait for it (register_chunk).
void SceneData::order_by_need(std::vector<ActingLink>& acting) {
  std::vector<std::vector<std::pair<int, int>>> incident(static_cast<std::size_t>(padded_masses)); // (file link, acting)
  for (std::size_t k = 0; k < acting.size(); ++k) {
    if (acting[k].creature < 0) continue;
    for (bool b_end : {false, true}) {
      const int w = working_end(acting[k], b_end);
      if (w < masses) incident[w].emplace_back(acting[k].link, static_cast<int>(k)); // a mass
    }
  }
  std::vector<int> after(acting.size(), -1); // rounds that follow the link's first use
  for (int blk = 0; blk < padded_masses; blk += kMaxWidth) {
    std::size_t rounds = 0;
    for (int w = blk; w < blk + kMaxWidth; ++w) rounds = std::max(rounds, incident[w].size());
    for (int w = blk; w < blk + kMaxWidth; ++w) {
      auto& list = incident[w];
      std::sort(list.begin(), list.end());
      for (std::size_t r = 0; r < list.size(); ++r) {
        int& a = after[static_cast<std::size_t>(list[r].second)];
        a = std::max(a, static_cast<int>(rounds - r));
      }
    }
  }
  std::vector<int> index(acting.size());
  for (std::size_t k = 0; k < acting.size(); ++k) index[k] = static_cast<int>(k);
  const auto by_need = [&](int x, int y) { return after[x] > after[y]; };
  std::stable_sort(index.begin(), index.begin() + padded_wave_muscles, by_need);
  std::stable_sort(index.begin() + padded_wave_muscles, index.end(), by_need);
  std::vector<ActingLink> ordered;
  for (int k : index) ordered.push_back(acting[k]);
  acting = ordered;
  std::fill(a_end_block.begin(), a_end_block.end(), -1); // the blocks no longer follow the masses
}

void SceneData::arrange_links(std::vector<ActingLink>& acting) {
  struct Arranged {
    std::vector<ActingLink> formed; ///< W per block
    std::vector<std::int32_t> blocks;
    std::vector<ActingLink> rest; ///< in the order given
  };
  const auto arrange = [&](const std::vector<ActingLink>& pool) {
    Arranged out;
    std::vector<std::vector<int>> incident(static_cast<std::size_t>(padded_masses));
    std::vector<int> left(static_cast<std::size_t>(padded_masses), 0); // unplaced links at each mass
    for (std::size_t g = 0; g < pool.size(); ++g) {
      const int a = working_end(pool[g], false), b = working_end(pool[g], true);
      if (a < masses) incident[a].push_back(static_cast<int>(g));
      if (b < masses && b != a) incident[b].push_back(static_cast<int>(g));
    }
    for (int m = 0; m < masses; ++m) left[m] = static_cast<int>(incident[m].size());
    std::vector<char> placed(pool.size(), 0);
    std::vector<std::size_t> first(static_cast<std::size_t>(padded_masses), 0); // before it: all placed
    const int dummies_allowed = W == 8 ? 1 : 0;
    for (bool progress = true; progress;) {
      progress = false;
      for (int blk = 0; blk < padded_masses / W; ++blk) {
        int ready = 0;
        for (int t = 0; t < W; ++t) ready += left[W * blk + t] > 0 ? 1 : 0;
        if (ready < W - dummies_allowed) continue;
        for (int t = 0; t < W; ++t) {
          const int m = W * blk + t;
          // Of the mass's next links (a bounded look, so that a mass of huge
          // degree costs linear time), the one whose other end has the most links
          // left (an end that is not a mass cannot be an A end: taken first).
          constexpr std::size_t kLook = 32;
          const auto& list = incident[m];
          std::size_t& from = first[m];
          while (from < list.size() && placed[list[from]]) ++from;
          int best = -1, best_left = -1;
          for (std::size_t q = from; q < list.size() && q < from + kLook; ++q) {
            const int g = list[q];
            if (placed[g]) continue;
            const int a = working_end(pool[g], false), b = working_end(pool[g], true);
            const int other = a == m ? b : a;
            const int other_left = other < masses ? left[other] : std::numeric_limits<int>::max();
            if (other_left > best_left) best = g, best_left = other_left;
          }
          ActingLink slot;
          if (best < 0) {
            slot.dummy = m;
          } else {
            slot = pool[best];
            const int a = working_end(slot, false), b = working_end(slot, true);
            slot.swapped = a != m;
            placed[best] = 1;
            --left[m];
            const int other = a == m ? b : a;
            if (other < masses && other != m) --left[other];
          }
          out.formed.push_back(slot);
        }
        out.blocks.push_back(blk);
        progress = true;
      }
    }
    for (std::size_t g = 0; g < pool.size(); ++g) {
      if (!placed[g]) out.rest.push_back(pool[g]);
    }
    return out;
  };
  const Arranged wave = arrange(std::vector<ActingLink>(acting.begin(), acting.begin() + wave_muscles));
  const Arranged other = arrange(std::vector<ActingLink>(acting.begin() + wave_muscles, acting.end()));
  acting = wave.formed;
  a_end_block = wave.blocks;
  acting.insert(acting.end(), wave.rest.begin(), wave.rest.end());
  std::size_t next = 0; // of other.rest
  while (acting.size() % kMaxWidth != 0) acting.push_back(next < other.rest.size() ? other.rest[next++] : ActingLink{});
  padded_wave_muscles = static_cast<int>(acting.size());
  a_end_block.resize(acting.size() / static_cast<std::size_t>(W), -1);
  acting.insert(acting.end(), other.formed.begin(), other.formed.end());
  a_end_block.insert(a_end_block.end(), other.blocks.begin(), other.blocks.end());
  acting.insert(acting.end(), other.rest.begin() + static_cast<std::ptrdiff_t>(next), other.rest.end());
  const std::size_t padded = (acting.size() + kMaxWidth - 1) / kMaxWidth * kMaxWidth;
  a_end_block.resize(padded / static_cast<std::size_t>(W), -1);
}

} // namespace soda::fused
