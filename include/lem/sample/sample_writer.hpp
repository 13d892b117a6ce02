// Writing the cemented sample file, on one rank or by every rank for its
// blocks.  The file's layout and its readers: lem/sample/sample_reader.hpp.
#pragma once

#include "lem/base/provenance.hpp"
#include "lem/sample/cemented_sample.hpp"
#include "lem/sample/sample_reader.hpp"

#include <mpi.h>

#include <string>

namespace lem {

/// Write <stem>.h5 and the three .xmf files, each under a temporary name renamed into
/// place when complete.  Serial: call on one rank.  Throws InputError if the
/// files cannot be written.
void write_sample(const std::string& stem, const CementedSample& sample,
                  const CementedSampleSpec& spec, const Provenance& provenance);

/// Collective: every rank writes its blocks of `sample` (the particles and
/// bridges from rank 0) to <stem>.h5 through parallel HDF5, under a temporary
/// name renamed into place when complete, then rank 0 the three .xmf files.
/// The same file as write_sample's for the same content, on any rank count
/// (datasets and attributes; the compression may lay the chunks out
/// differently).  Throws the same IoError on every rank if it cannot be written.
void write_sample_block(MPI_Comm comm, const std::string& stem, const SampleBlock& sample);

}  // namespace lem
