#include "render/photo_loader.h"

namespace hdribr::render {

PhotoLoader::PhotoLoader(const Scene& scene, const std::vector<cv::Mat>& images,
                         const PhotoLayout& layout)
    : scene_(scene), images_(images), layout_(layout), thread_([this] { Work(); }) {}

PhotoLoader::~PhotoLoader() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    queue_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void PhotoLoader::Request(int photo) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(photo);
  }
  wake_.notify_one();
}

std::vector<LoadedPhoto> PhotoLoader::TakeDone() {
  const std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(finished_, {});
}

std::vector<LoadedPhoto> PhotoLoader::WaitDone(size_t count) {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return finished_.size() >= count; });
  return std::exchange(finished_, {});
}

void PhotoLoader::Work() {
  for (;;) {
    int photo = -1;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      photo = queue_.front();
      queue_.pop_front();
    }
    LoadedPhoto loaded;
    loaded.photo = photo;
    try {
      loaded.pixels = LoadPhotoPixels(scene_, images_, layout_, static_cast<size_t>(photo));
    } catch (...) {
      loaded.error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      finished_.push_back(std::move(loaded));
    }
    done_.notify_all();
  }
}

}  // namespace hdribr::render
