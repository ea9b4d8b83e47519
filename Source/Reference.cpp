// REFERENCE: plain temporal accumulation (the ground truth for a still camera), document 004.
#include "InstanceImpl.h"

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#include "../Shaders/Reference/Reference_Accumulate.resources.h"
} // namespace passes

namespace
{

class Reference final : public MethodBase
{
public:
    explicit Reference(MethodBuilder& builder)
    {
        ResourceRef history = builder.AddPermanentTexture(Format::RGBA32_SFLOAT);
        m_Accumulate = builder.AddDispatch<passes::Reference_Accumulate>(
            "REFERENCE - Accumulate", {App(ResourceType::IN_RADIANCE), history, App(ResourceType::OUT_RADIANCE)});
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::REFERENCE)
        {
            log.Error("SetMethodSettings: REFERENCE takes ReferenceSettings");
            return Result::INVALID_ARGUMENT;
        }
        const ReferenceSettings& s = *static_cast<const ReferenceSettings*>(settings);
        if (s.maxAccumulatedFrameNum < 1 || s.maxAccumulatedFrameNum > REFERENCE_MAX_HISTORY_FRAME_NUM)
        {
            log.Error("SetMethodSettings: ReferenceSettings::maxAccumulatedFrameNum %u is outside [1, %u]",
                      s.maxAccumulatedFrameNum, REFERENCE_MAX_HISTORY_FRAME_NUM);
            return Result::INVALID_ARGUMENT;
        }
        m_Settings = s;
        return Result::SUCCESS;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        m_Accumulated = frame.resetHistory ? 1 : m_Accumulated + 1;
        if (m_Accumulated > m_Settings.maxAccumulatedFrameNum)
            m_Accumulated = m_Settings.maxAccumulatedFrameNum;

        passes::Reference_Accumulate::Constants c = {};
        c.gSize = {frame.width, frame.height};
        c.gWeight = 1.0f / float(m_Accumulated);
        context.Dispatch(m_Accumulate, c, frame.width, frame.height);
    }

private:
    ReferenceSettings m_Settings = {};
    uint32_t m_Accumulate = 0;
    uint32_t m_Accumulated = 0;
};

} // namespace

std::unique_ptr<MethodBase> CreateReference(MethodBuilder& builder, Method)
{
    return std::unique_ptr<MethodBase>(new Reference(builder));
}

} // namespace nrd
