#pragma once

/// \file
/// The athlete's 2D keypoints as a step of the pipeline (docs/pose.md): the tracker's region
/// from the trampoline's bed, and where a door that detects on demand (the studio) keeps a
/// video's detections — the same folder `acrolab detect VIDEO -o <its folder>/acrolab-detect`
/// writes, so that either fills it for the other and a second run resumes or reads it back.

#include <filesystem>
#include <vector>

#include "acro/base/progress.h"
#include "acro/pose/video_poses.h"

namespace acro::pipeline {

/// The bed found in frame `frame` of `video` (vision::DetectBed) as the tracker's region. With
/// `required` false a video without a bed found leaves `tracker` as it was; with true, that throws
/// acro::InputError naming the video.
void RegionFromBed(const std::filesystem::path& video,
                   int frame,
                   bool required,
                   pose::PoseTrackerOptions* tracker);

/// Where a video's detections are kept: `<the video's folder>/acrolab-detect/<its stem>/`, or,
/// when that folder cannot be written (a read-only share, a card), the user's cache
/// (`$XDG_CACHE_HOME` or `~/.cache`)`/acrolab/detect/<16 hex of the SHA-256 of the video's
/// absolute path>/<its stem>/`.
std::filesystem::path PoseCacheDirectory(const std::filesystem::path& video);

/// The video's poses with the model asked, the bed's region when there is one, into its
/// PoseCacheDirectory (resuming there). `progress` as acro::Progress: false stops it with
/// acro::Cancelled, the frames done kept for the next run.
pose::VideoPoses DetectPosesInCache(const std::filesystem::path& video,
                                    pose::LandmarkModel model,
                                    const Progress& progress = {});

/// DetectPosesInCache for several videos, side by side (one network thread each, as `acrolab
/// detect` runs them), in the order given. `progress` hears "detect" with the frames of all videos
/// together, one call at a time.
std::vector<pose::VideoPoses> DetectPosesInCache(const std::vector<std::filesystem::path>& videos,
                                                 pose::LandmarkModel model,
                                                 const Progress& progress = {});

/// A video's poses as detections in the BODY_25B set (pose::Body25bFromBlazePose: the hips where
/// OpenPose puts them), frame k the video's frame k; frames without a pose are empty.
capture::KeypointDetections Body25bDetections(const pose::VideoPoses& poses);

}  // namespace acro::pipeline
