#include "app/board_lights.h"

#include <map>
#include <vector>

#include "core/directions.h"
#include "core/session_layout.h"
#include "formats/lp_file.h"

namespace mesocap::app {

Status WriteBoardLightFiles(const std::filesystem::path& slices_dir, const ResampleReport& slices) {
  std::map<int, std::vector<LpEntry>> boards;
  for (const SliceRecord& r : slices.slices)
    boards[r.board].push_back({slices_dir / r.file, DirectionFromAnglesDeg(r.theta_i_deg, r.phi_i_deg)});
  for (const auto& [board, entries] : boards)
    if (Status st = WriteLpFile(SlicesFolder{slices_dir}.board_lights(board), entries); !st.ok()) return st;
  return Status::Ok();
}

}  // namespace mesocap::app
