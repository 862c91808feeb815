function setup_path()
%% add DDE-BIFTOOL to the path; location from env DDEBIFTOOL
base=getenv('DDEBIFTOOL');
if isempty(base), error('set DDEBIFTOOL to the DDE-BIFTOOL checkout'); end
addpath(fullfile(base,'ddebiftool'),fullfile(base,'ddebiftool_extra_psol'),...
    fullfile(base,'ddebiftool_utilities'));
if exist('OCTAVE_VERSION','builtin'), warning('off','all'); end
end
