#include "lem/files.hpp"

#include "lem/error.hpp"

#include <filesystem>
#include <fstream>
#include <system_error>

namespace lem {

namespace fs = std::filesystem;

void write_text_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw InputError("cannot write file '" + path + "': cannot create '" + tmp + "'");
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    out.close();
    if (out.fail()) {
      fs::remove(tmp, ec);
      throw InputError("cannot write file '" + path + "': writing '" + tmp + "' failed");
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(tmp, ec);
    throw InputError("cannot write file '" + path + "': renaming '" + tmp + "' failed: " + reason);
  }
}

void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files) {
  run_on_root(comm, [&] {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
      throw InputError("output directory '" + dir + "' cannot be created: " + ec.message());
    for (const auto& f : result_files) std::filesystem::remove(dir + "/" + f, ec);
  });
}

}  // namespace lem
