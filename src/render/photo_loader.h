// A worker thread that reads and downscales photos (CPU, OpenCV) for the photo cache, so that
// the GL thread only uploads them.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <opencv2/core.hpp>
#include <thread>
#include <utility>
#include <vector>

#include "core/scene.h"
#include "render/photo_textures.h"

namespace hdribr::render {

// A photo's pixels as LoadPhotoPixels gives them, or the error that loading it threw.
struct LoadedPhoto {
  int photo = -1;
  cv::Mat pixels;
  std::exception_ptr error;
};

class PhotoLoader {
 public:
  // Keeps references to `scene`, `images` and `layout`, which must outlive the loader.
  PhotoLoader(const Scene& scene, const std::vector<cv::Mat>& images, const PhotoLayout& layout);
  ~PhotoLoader();  // drops the queued requests and joins the thread
  PhotoLoader(const PhotoLoader&) = delete;
  PhotoLoader& operator=(const PhotoLoader&) = delete;

  // Queues photo i (index into scene.photos).
  void Request(int photo);
  // The photos loaded since the last call, without waiting.
  std::vector<LoadedPhoto> TakeDone();
  // Waits until `count` photos are done (queued ones included), then takes them all.
  std::vector<LoadedPhoto> WaitDone(size_t count);

 private:
  void Work();

  const Scene& scene_;
  const std::vector<cv::Mat>& images_;
  const PhotoLayout& layout_;
  std::mutex mutex_;
  std::condition_variable wake_;  // a request or the end
  std::condition_variable done_;  // a photo finished
  std::deque<int> queue_;
  std::vector<LoadedPhoto> finished_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace hdribr::render
