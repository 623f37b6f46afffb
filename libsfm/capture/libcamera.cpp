/*
 * libcamera source: a C++17 adapter in libcamera's own style behind the
 * extern "C" functions of sfm_capture.h.
 *
 * It uses only API present in libcamera 0.0.3 (Debian 12) and in the later
 * releases boards run: CameraManager::start/cameras/get, Camera::acquire/
 * generateConfiguration (given a std::vector of roles, which converts to the
 * Span later releases take)/configure/createRequest/queueRequest/start/stop/
 * release, CameraConfiguration::validate, FrameBufferAllocator, Request::
 * addBuffer/findBuffer/reuse, FrameBuffer::planes/metadata, the
 * requestCompleted and disconnected signals. Nothing of orientation,
 * transforms or controls, whose API changed between releases.
 *
 * The completion callback runs in libcamera's thread and only pushes the
 * request into a fixed ring; everything else happens in the caller's
 * thread inside acquire/release. CameraManager allows one instance per
 * process, so sources share one, counted.
 */
#include <sys/mman.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

extern "C" {
#include "capture/capture_impl.h"
}

#ifdef SFM_HAVE_LIBCAMERA
#include <libcamera/libcamera.h>

using namespace libcamera;

namespace {

/* The process-wide camera manager, started on first use. */
std::mutex managerMutex;
std::unique_ptr<CameraManager> manager;
int managerUsers;

CameraManager *managerGet()
{
	std::lock_guard<std::mutex> lock(managerMutex);
	if (!manager) {
		auto cm = std::make_unique<CameraManager>();
		if (cm->start() != 0)
			return nullptr;
		manager = std::move(cm);
	}
	managerUsers++;
	return manager.get();
}

void managerPut()
{
	std::lock_guard<std::mutex> lock(managerMutex);
	if (--managerUsers == 0) {
		manager->stop();
		manager.reset();
	}
}

constexpr unsigned int kRingSize = 32;

int pixfmtOf(const PixelFormat &f)
{
	if (f == formats::R8)
		return SFM_PIX_GRAY8;
	if (f == formats::YUV420 || f == formats::NV12)
		return SFM_PIX_NV12; /* luma plane first, then chroma */
	if (f == formats::YUYV)
		return SFM_PIX_YUYV;
	return 0;
}

class LibcameraSource
{
public:
	~LibcameraSource();

	int open(const char *cameraId, const sfm_libcamera_options &opt,
		 sfm_capture_info *info);
	int acquire(sfm_capture_stats *stats, int timeoutMs, sfm_frame *frame);
	int release();

private:
	struct Mapping {
		void *address = MAP_FAILED;
		size_t length = 0;
		const uint8_t *plane0 = nullptr;
	};

	void requestComplete(Request *request);
	void cameraDisconnected();
	int requeue(Request *request);
	void teardown();

	CameraManager *cm_ = nullptr;
	std::shared_ptr<Camera> camera_;
	bool acquired_ = false;
	bool started_ = false;
	bool connected_ = false;
	std::unique_ptr<CameraConfiguration> config_;
	Stream *stream_ = nullptr;
	std::unique_ptr<FrameBufferAllocator> allocator_;
	std::vector<std::unique_ptr<Request>> requests_;
	std::vector<Mapping> mappings_;
	std::vector<uint8_t> gray_;
	int format_ = 0;
	unsigned int width_ = 0, height_ = 0, stride_ = 0;

	/* Filled by libcamera's thread, drained by the caller's. */
	std::mutex mutex_;
	std::condition_variable ready_;
	Request *ring_[kRingSize] = {};
	unsigned int head_ = 0, count_ = 0;
	std::atomic<bool> lost_{ false };

	Request *held_ = nullptr;
	bool haveSequence_ = false;
	unsigned int lastSequence_ = 0;
};

LibcameraSource::~LibcameraSource()
{
	teardown();
}

void LibcameraSource::teardown()
{
	if (camera_) {
		if (started_)
			camera_->stop();
		started_ = false;
		if (connected_) {
			camera_->requestCompleted.disconnect(this, &LibcameraSource::requestComplete);
			camera_->disconnected.disconnect(this, &LibcameraSource::cameraDisconnected);
			connected_ = false;
		}
	}
	for (Mapping &m : mappings_)
		if (m.address != MAP_FAILED)
			munmap(m.address, m.length);
	mappings_.clear();
	held_ = nullptr;
	{
		std::lock_guard<std::mutex> lock(mutex_);
		count_ = 0;
	}
	requests_.clear();
	if (allocator_ && stream_)
		allocator_->free(stream_);
	allocator_.reset();
	config_.reset();
	if (camera_ && acquired_)
		camera_->release();
	acquired_ = false;
	camera_.reset();
	if (cm_)
		managerPut();
	cm_ = nullptr;
}

void LibcameraSource::requestComplete(Request *request)
{
	std::lock_guard<std::mutex> lock(mutex_);
	if (count_ < kRingSize) {
		ring_[(head_ + count_) % kRingSize] = request;
		count_++;
	}
	ready_.notify_one();
}

void LibcameraSource::cameraDisconnected()
{
	lost_ = true;
	std::lock_guard<std::mutex> lock(mutex_);
	ready_.notify_one();
}

int LibcameraSource::open(const char *cameraId, const sfm_libcamera_options &opt,
			  sfm_capture_info *info)
{
	cm_ = managerGet();
	if (!cm_)
		return SFM_E_IO;

	if (cameraId) {
		camera_ = cm_->get(cameraId);
	} else {
		std::vector<std::shared_ptr<Camera>> cameras = cm_->cameras();
		if (!cameras.empty())
			camera_ = cameras.front();
	}
	if (!camera_)
		return SFM_E_NO_DEVICE;
	if (camera_->acquire() != 0)
		return SFM_E_IO;
	acquired_ = true;

	std::vector<StreamRole> roles{ StreamRole::Viewfinder };
	config_ = camera_->generateConfiguration(roles);
	if (!config_ || config_->size() != 1)
		return SFM_E_UNSUPPORTED;
	StreamConfiguration &cfg = config_->at(0);
	cfg.pixelFormat = formats::YUV420;
	if (opt.width > 0 && opt.height > 0)
		cfg.size = Size(static_cast<unsigned int>(opt.width),
				static_cast<unsigned int>(opt.height));
	cfg.bufferCount = static_cast<unsigned int>(opt.buffers > 0 ? opt.buffers : 4);

	/* validate() may adjust the request; an invalid one is an error, an
	 * adjusted one is reported through info->adjusted. */
	CameraConfiguration::Status status = config_->validate();
	if (status == CameraConfiguration::Invalid)
		return SFM_E_UNSUPPORTED;
	info->adjusted = status == CameraConfiguration::Adjusted;
	format_ = pixfmtOf(cfg.pixelFormat);
	if (format_ == 0 || cfg.bufferCount < 2 || cfg.bufferCount > kRingSize ||
	    cfg.size.width == 0 || cfg.size.height == 0 ||
	    cfg.size.width > SFM_CAPTURE_MAX_SIDE || cfg.size.height > SFM_CAPTURE_MAX_SIDE)
		return SFM_E_UNSUPPORTED;
	if (camera_->configure(config_.get()) != 0)
		return SFM_E_IO;
	stream_ = cfg.stream();
	width_ = cfg.size.width;
	height_ = cfg.size.height;
	const unsigned int row = format_ == SFM_PIX_YUYV ? 2 * width_ : width_;
	stride_ = cfg.stride ? cfg.stride : row;
	if (stride_ < row)
		return SFM_E_UNSUPPORTED;

	allocator_ = std::make_unique<FrameBufferAllocator>(camera_);
	if (allocator_->allocate(stream_) < 2)
		return SFM_E_IO;
	const std::vector<std::unique_ptr<FrameBuffer>> &buffers = allocator_->buffers(stream_);
	if (buffers.size() > kRingSize)
		return SFM_E_UNSUPPORTED;

	const size_t lumaBytes = static_cast<size_t>(stride_) * (height_ - 1) + row;
	for (unsigned int i = 0; i < buffers.size(); i++) {
		const FrameBuffer::Plane &plane = buffers[i]->planes()[0];
		const size_t offset = plane.offset == FrameBuffer::Plane::kInvalidOffset ? 0 : plane.offset;
		if (plane.length < lumaBytes)
			return SFM_E_UNSUPPORTED;
		Mapping m;
		m.length = offset + plane.length;
		m.address = mmap(nullptr, m.length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
		if (m.address == MAP_FAILED)
			return SFM_E_IO;
		m.plane0 = static_cast<const uint8_t *>(m.address) + offset;
		mappings_.push_back(m);

		std::unique_ptr<Request> request = camera_->createRequest(i);
		if (!request || request->addBuffer(stream_, buffers[i].get()) != 0)
			return SFM_E_IO;
		requests_.push_back(std::move(request));
	}
	gray_.resize(static_cast<size_t>(width_) * height_);

	camera_->requestCompleted.connect(this, &LibcameraSource::requestComplete);
	camera_->disconnected.connect(this, &LibcameraSource::cameraDisconnected);
	connected_ = true;
	if (camera_->start() != 0)
		return SFM_E_IO;
	started_ = true;
	for (std::unique_ptr<Request> &request : requests_)
		if (camera_->queueRequest(request.get()) != 0)
			return SFM_E_IO;

	info->width = static_cast<int>(width_);
	info->height = static_cast<int>(height_);
	info->source_format = format_;
	info->fourcc = cfg.pixelFormat.fourcc();
	info->source_stride = static_cast<int>(stride_);
	info->buffers = static_cast<int>(buffers.size());
	sfm_capture_strlcpy(info->driver, sizeof info->driver, "libcamera");
	sfm_capture_strlcpy(info->card, sizeof info->card, camera_->id().c_str());
	return SFM_OK;
}

int LibcameraSource::requeue(Request *request)
{
	request->reuse(Request::ReuseBuffers);
	return camera_->queueRequest(request) == 0 ? SFM_OK : SFM_E_DEVICE_LOST;
}

int LibcameraSource::acquire(sfm_capture_stats *stats, int timeoutMs, sfm_frame *frame)
{
	if (!started_)
		return SFM_E_DEVICE_LOST;
	const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
	for (;;) {
		Request *request;
		{
			std::unique_lock<std::mutex> lock(mutex_);
			auto ready = [this] { return count_ > 0 || lost_; };
			if (timeoutMs < 0)
				ready_.wait(lock, ready);
			else if (!ready_.wait_until(lock, deadline, ready))
				return SFM_E_TIMEOUT;
			if (lost_) {
				lock.unlock();
				teardown();
				return SFM_E_DEVICE_LOST;
			}
			request = ring_[head_];
			head_ = (head_ + 1) % kRingSize;
			count_--;
		}
		if (request->status() == Request::RequestCancelled)
			continue; /* only while stopping */
		const FrameBuffer *buffer = request->findBuffer(stream_);
		const uint64_t index = request->cookie();
		if (!buffer || index >= mappings_.size())
			return SFM_E_IO;
		const FrameMetadata &md = buffer->metadata();
		if (haveSequence_ && md.sequence - lastSequence_ > 1u &&
		    md.sequence - lastSequence_ < 0x80000000u)
			stats->drops += md.sequence - lastSequence_ - 1u;
		haveSequence_ = true;
		lastSequence_ = md.sequence;

		const uint8_t *luma = mappings_[index].plane0;
		if (md.status != FrameMetadata::FrameSuccess) {
			stats->errors++;
			if (requeue(request) != SFM_OK) {
				teardown();
				return SFM_E_DEVICE_LOST;
			}
			continue;
		}
		frame->width = static_cast<int>(width_);
		frame->height = static_cast<int>(height_);
		frame->format = SFM_PIX_GRAY8;
		frame->timestamp_ns = static_cast<int64_t>(md.timestamp);
		frame->sequence = md.sequence;
		frame->slot = static_cast<int>(index);
		if (format_ == SFM_PIX_YUYV) {
			sfm_gray_from_yuyv(luma, static_cast<int>(stride_), frame->width,
					   frame->height, gray_.data(), frame->width);
			frame->data = gray_.data();
			frame->stride = frame->width;
			if (requeue(request) != SFM_OK)
				teardown(); /* delivered; the loss shows on the next call */
		} else {
			frame->data = luma;
			frame->stride = static_cast<int>(stride_);
			held_ = request;
		}
		return 1;
	}
}

int LibcameraSource::release()
{
	if (!started_)
		return SFM_E_DEVICE_LOST;
	if (!held_)
		return SFM_OK;
	Request *request = held_;
	held_ = nullptr;
	if (requeue(request) != SFM_OK) {
		teardown();
		return SFM_E_DEVICE_LOST;
	}
	return SFM_OK;
}

int vtAcquire(sfm_capture *c, int timeoutMs, sfm_frame *frame)
{
	try {
		return static_cast<LibcameraSource *>(c->impl)->acquire(&c->stats, timeoutMs, frame);
	} catch (...) {
		return SFM_E_IO;
	}
}

int vtRelease(sfm_capture *c, const sfm_frame *frame)
{
	(void)frame;
	try {
		return static_cast<LibcameraSource *>(c->impl)->release();
	} catch (...) {
		return SFM_E_IO;
	}
}

void vtDestroy(sfm_capture *c)
{
	delete static_cast<LibcameraSource *>(c->impl);
}

const sfm_capture_vtbl libcameraVtbl = { vtAcquire, vtRelease, vtDestroy };

} /* namespace */

extern "C" int sfm_libcamera_list(char *ids, int max_ids, int id_len)
{
	if ((ids != nullptr && (max_ids < 0 || id_len < 1)) ||
	    (ids == nullptr && max_ids != 0))
		return SFM_E_ARGUMENT;
	try {
		CameraManager *cm = managerGet();
		if (!cm)
			return SFM_E_IO;
		std::vector<std::shared_ptr<Camera>> cameras = cm->cameras();
		int n = static_cast<int>(cameras.size());
		for (int i = 0; ids && i < n && i < max_ids; i++)
			sfm_capture_strlcpy(ids + static_cast<size_t>(i) * id_len,
					    static_cast<size_t>(id_len), cameras[i]->id().c_str());
		cameras.clear();
		managerPut();
		return n;
	} catch (...) {
		return SFM_E_IO;
	}
}

extern "C" int sfm_capture_open_libcamera(const char *camera_id,
					  const sfm_libcamera_options *opt,
					  sfm_capture **out)
{
	if (out == nullptr || (camera_id && camera_id[0] == '\0'))
		return SFM_E_ARGUMENT;
	sfm_libcamera_options o = { 0, 0, 0 };
	if (opt)
		o = *opt;
	if (o.width < 0 || o.height < 0 || o.width > SFM_CAPTURE_MAX_SIDE ||
	    o.height > SFM_CAPTURE_MAX_SIDE || o.buffers < 0 || o.buffers == 1 ||
	    o.buffers > static_cast<int>(kRingSize))
		return SFM_E_ARGUMENT;
	try {
		auto source = std::make_unique<LibcameraSource>();
		sfm_capture_info info;
		std::memset(&info, 0, sizeof info);
		int ret = source->open(camera_id, o, &info);
		if (ret != SFM_OK)
			return ret; /* the destructor undoes what open did */
		sfm_capture *c = sfm_capture_new(&libcameraVtbl, source.get());
		if (!c)
			return SFM_E_IO;
		source.release();
		c->info = info;
		*out = c;
		return SFM_OK;
	} catch (...) {
		return SFM_E_IO;
	}
}

#else /* built without libcamera */

extern "C" int sfm_libcamera_list(char *ids, int max_ids, int id_len)
{
	(void)ids;
	(void)max_ids;
	(void)id_len;
	return SFM_E_UNSUPPORTED;
}

extern "C" int sfm_capture_open_libcamera(const char *camera_id,
					  const sfm_libcamera_options *opt,
					  sfm_capture **out)
{
	(void)camera_id;
	(void)opt;
	(void)out;
	return SFM_E_UNSUPPORTED;
}

#endif
