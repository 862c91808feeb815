function torus(stage,degree,intervals,tau0,kref,kstart,krange,which)
%% The torus (Neimark-Sacker) bifurcation of the 2-slip orbit (the branch born
% at the second Hopf point in k at tau = 10, defaults of eq. 8, d = 1e-4).
% stage 'point': the branch from the Hopf point down past k = 5.2 (free k, c),
%   the orbit at k = 5.20, 5.2567084, 5.30 with all multipliers near -1, the
%   zero of |mu| - 1 of the pair near -1 by secant over k; then the torus point
%   itself from SetupTorusBifurcation at tau = 10 (free k, c, omega).
%   Saves torus_point.mat.
% stage 'curve': SetupTorusBifurcation continued in (k, tau) from tau = 10
%   (bounds taulo, tauhi), points at exactly the tau of slopetui's curve
%   corrected from the nearest curve point with tau fixed.
% The co-moving frame's pinning z(0) = 0 (slope_funcs' sys_cond) is not part
% of DDE-BIFTOOL's torus system (it collects only its own conditions), so it is
% passed as extra_cond on the solution's z row; the torus eigenvector needs
% none: the translation e_z has multiplier 1, not e^{+-i pi omega}.
if nargin<1, stage='point'; end
if nargin<2, degree=4; end
if nargin<3, intervals=60; end
% tau0, kref: where the torus is sought (kref: slopetui's k, only to centre
% the secant's two start points at kref -+ 1%, and to print the difference);
% kstart, krange: the steady-state sweep in k that finds the second Hopf point
if nargin<4, tau0=10; end
if nargin<5, kref=5.2567084; end
if nargin<6, kstart=5.5; end
if nargin<7, krange=2; end
% which: the Hopf point the branch starts at (2: the 2-slip orbit, its pair
% near -1; 3: the 3-slip orbit, its pairs near exp(+-2 pi i/3))
if nargin<8, which=2; end
setup_path();
t0=tic;
switch stage
    case 'point', torus_point(degree,intervals,t0,tau0,kref,kstart,krange,which);
    otherwise, torus_curve(stage,t0);
end
end

function torus_point(degree,intervals,t0,tau0,kref,kstart,krange,which)
if nargin<8, which=2; end
target=exp(2i*pi/which);   % -1 for the 2-slip orbit
fprintf('collocation: degree %d, %d intervals (adaptive mesh)\n',degree,intervals);
% the second Hopf point of the sweep in k at tau = 10 (k_H = 6.678)
[~,~,funcs,ip,hbr]=hopf_point(tau0,kstart,true,which,krange);
[pbr,suc]=SetupPsol(funcs,hbr,1,'contpar',[ip.k,ip.c],'degree',degree,...
    'intervals',intervals,'radius',1e-3,'max_bound',[ip.k,max(7.5,1.2*kref)],'min_bound',[ip.k,0.3]);
if ~suc, error('psol init failed'); end
pbr.method.continuation.plot=0;
pbr.method.point.extra_condition=1;
pbr.method.continuation.steplength_growth_factor=1.2;
pbr.method.point.adapt_mesh_after_correct=1;
pbr.method.point.adapt_mesh_before_correct=1;
pbr.parameter.max_step=[ip.k,0.1*max(1,kref/5);0,0.2*max(1,kref/5)];
% down from the Hopf point, through the fold of this branch, and back up past
% kref (at tau = 10 the 2-slip orbit slopetui continues is the branch beyond the fold)
for it=1:40
    pbr=br_contn(funcs,pbr,10);
    k=orbit_measures(pbr.point,ip); [~,i]=min(k);
    if i<numel(k)-2 && k(end)>1.02*kref, break; end
end
for i=1:numel(k)
    fprintf('BRANCHPT k=%.8f T=%.8f\n',k(i),pbr.point(i).period);
end
fprintf('BRANCH %d points, k from %.6f to %.6f, T at the end %.6f (%.0fs)\n',numel(k),...
    k(1),k(end),pbr.point(end).period,toc(t0));

% the points past the branch's fold in k
[~,ifold]=min(k); idx=ifold:numel(k);
ks=kref*[0.99,1,1.01]; g=zeros(size(ks)); pts=[];
for i=1:numel(ks)
    [pt,ok]=orbit_at_k(funcs,pbr,ip,ks(i),idx);
    if ~ok, error('orbit at k=%g failed',ks(i)); end
    [g(i),pt]=pair_report(funcs,pbr,pt,ip,'ORBIT',target);
    pts=[pts,pt]; %#ok<AGROW>
end
% secant on g(k) = |mu| - 1 of the pair near -1, from k = 5.20 and 5.30
ka=ks(1); ga=g(1); kb=ks(3); gb=g(3); pa=pts(1); pb=pts(3);
for it=1:6
    kn=kb-gb*(kb-ka)/(gb-ga);
    start=pb; if abs(ka-kn)<abs(kb-kn), start=pa; end
    start.parameter(ip.k)=kn; start.stability=[];
    [pn,ok]=p_correc(funcs,start,ip.c,[],pbr.method.point);
    if ~ok, error('secant orbit at k=%.9f failed',kn); end
    [gn,pn]=pair_report(funcs,pbr,pn,ip,'SECANT',target);
    ka=kb; ga=gb; pa=pb; kb=kn; gb=gn; pb=pn;
    if abs(kb-ka)<1e-8, break; end
end
fprintf('SECANT |mu|-1 = 0 at k=%.9f (tau=%g; slopetui %.9g, diff %.2e, rel %.1e), T=%.8f (%.0fs)\n',...
    kb,tau0,kref,kb-kref,(kb-kref)/kref,pb.period,toc(t0));
ptor=pb;
% DDE-BIFTOOL's own torus system at tau = 10, free k, c (and omega, period)
br=pbr; br.point=ptor;
[trfuncs,trbr,suc]=torus_setup(funcs,br,ip,[ip.k,ip.c],target);
if ~suc, fprintf('TORUS SetupTorusBifurcation at tau=%g failed\n',tau0); end
s=trfuncs.get_comp(trbr.point(1),'solution'); om=trfuncs.get_comp(trbr.point(1),'omega');
fprintf('TORUS tau=%g success=%d k=%.9f T=%.8f omega=%.9f (mu = exp(+-i pi omega) = %.9f +- %.3ei) | slopetui %.9g diff %.2e (%.0fs)\n',...
    tau0,suc,s.parameter(ip.k),s.period,om,cos(pi*om),abs(sin(pi*om)),kref,s.parameter(ip.k)-kref,toc(t0));
if which==2, fn=sprintf('torus_point_%g.mat',tau0); else, fn=sprintf('torus_point_%g_%dslip.mat',tau0,which); end
save('-mat',fn,'ptor','pbr','ip');
end

function [trfuncs,trbr,suc]=torus_setup(funcs,br,ip,contpar,target)
%% SetupTorusBifurcation at br.point(1); the critical pair is the one near
% target (upper half plane), the largest in modulus if there are two
if nargin<5, target=-1; end
dim=size(br.point(1).profile,1);
st=dde_psol_eig(funcs,br.point(1),br.method.stability);
mu=st.mu(:); up=mu(abs(mu-target)<0.05 & imag(mu)>=0); [~,j]=max(abs(up)); mu=up;
[trfuncs,trbr,suc]=SetupTorusBifurcation(funcs,br,1,'contpar',contpar,...
    'nremove',[1,1],'closest',mu(j),'sys_deri',1e-6,'dir',[],...
    'extra_cond',{@(p,pref)solpin(p)});
trbr.method.point.adapt_mesh_after_correct=1;
trbr.method.point.adapt_mesh_before_correct=1;
trbr.method.continuation.plot=0;
end

function [r,J]=solpin(p)
%% z(0) = 0 on the solution part of the torus system (row 1 of the profile)
r=p.profile(1,1);
J=p_axpy(0,p,[]); J.profile(1,1)=1;
end

function [g,pt]=pair_report(funcs,br,pt,ip,tag,target)
%% multipliers of pt near -1; g = sqrt(|mu1 mu2|) - 1 of the two closest to -1:
% |mu| - 1 while they are a complex pair, and smooth in k where they split
% into two reals (at tau = 20 they are complex only within about 1e-3 of the
% torus in k: -1.000109, -1.000017 at k = 2.2010; -0.999985, -0.999907 at
% 2.2454), where |mu| - 1 of the larger one has a kink
if nargin<6, target=-1; end
br.point=pt;
[~,~,~,p2]=GetStability(br,'funcs',funcs,'exclude_trivial',false);
pt=p2(1); mu=pt.stability.mu(:);
[~,o]=sort(abs(mu+1)); near=mu(o(1:2));
[~,o1]=sort(abs(mu-1)); triv=mu(o1(1:2));
g=sqrt(abs(near(1)*near(2)))-1;
if abs(target+1)>1e-12
    % 3-slip: the pairs near exp(+-2 pi i/3); g = |mu| - 1 of the largest
    up=mu(abs(mu-target)<0.05 & imag(mu)>=0); [~,o]=sort(abs(up),'descend');
    near=up(o); g=abs(near(1))-1;
end
fprintf('%s k=%.9f T=%.8f mu near -1: %s |mu|-1: %s sqrt(|mu1 mu2|)-1: %.4g; trivial |mu-1| %.1e %.1e\n',tag,...
    pt.parameter(ip.k),pt.period,mat2str(near.',10),mat2str(abs(near.')-1,4),g,...
    abs(triv(1)-1),abs(triv(2)-1));
end

function torus_curve(spec,t0)
%% spec = 'curve:taulo:tauhi'
a=strsplit(spec,':'); taulo=str2double(a{2}); tauhi=str2double(a{3});
S=load('torus_point_10.mat'); funcs=slope_funcs(); ip=S.ip; pbr=S.pbr;
br=pbr; br.point=S.ptor;
[trfuncs,trbr,suc]=torus_setup(funcs,br,ip,[ip.k,ip.tau,ip.c]);
if ~suc, fprintf('TORUS SetupTorusBifurcation with tau free failed\n'); return; end
trbr.parameter.min_bound=[ip.tau,taulo];
trbr.parameter.max_bound=[ip.tau,tauhi];
trbr.parameter.max_step=[ip.tau,0.25;ip.k,0.5];
trbr.method.continuation.steplength_growth_factor=1.2;
tau0=trbr.point(1).parameter(ip.tau);
fprintf('TORUS start tau=%.8f k=%.9f (%.0fs)\n',tau0,trbr.point(1).parameter(ip.k),toc(t0));
fixed=setdiff(trbr.parameter.free,ip.tau);
curve=[];
for dir=[-1,1]
    if (dir<0 && taulo>=tau0) || (dir>0 && tauhi<=tau0), continue; end
    t1=tic;
    b=trbr; b.point=trbr.point(1);
    p2=b.point(1); p2.parameter(ip.tau)=tau0+dir*0.02;
    [p2,ok]=p_correc(trfuncs,p2,fixed,[],b.method.point);
    if ~ok, fprintf('TORUS second point (dir %+d) failed\n',dir); continue; end
    b.point(2)=p2;
    b=br_contn(trfuncs,b,300);
    pts=b.point; if dir<0, pts=fliplr(pts); end
    if isempty(curve), curve=pts; else, curve=[curve(1:end-1),pts(2:end)]; end %#ok<AGROW>
    fprintf('TORUSCURVE leg %+d: %d points, %.0fs\n',dir,numel(b.point),toc(t1));
end
sols=arrayfun(@(p)trfuncs.get_comp(p,'solution'),curve);
om=arrayfun(@(p)trfuncs.get_comp(p,'omega'),curve);
tau=arrayfun(@(p)p.parameter(ip.tau),sols); [tau,o]=sort(tau);
curve=curve(o); sols=sols(o); om=om(o);
k=arrayfun(@(p)p.parameter(ip.k),sols); T=[sols.period];
for i=1:numel(curve)
    fprintf('TORUSCURVE tau=%.6f k=%.9f T=%.8f omega=%.9f\n',tau(i),k(i),T(i),om(i));
end
% slopetui's curve: tau and k (core.torus_continuation, RK4, N = 1000)
ref=[10.5,4.927606587; 20,2.2231999; 8.56365,6.4813000; 5.162098,13.373043; 2,60.828202];
for r=1:size(ref,1)
    tt=ref(r,1);
    if tt<tau(1)-1e-9 || tt>tau(end)+1e-9, continue; end
    [d,j]=min(abs(tau-tt));
    pt=curve(j); pt.parameter(ip.tau)=tt;
    [pt,ok]=p_correc(trfuncs,pt,fixed,[],trbr.method.point);
    s=trfuncs.get_comp(pt,'solution'); w=trfuncs.get_comp(pt,'omega');
    fprintf('TORUS tau=%g success=%d k=%.9f T=%.8f mu=%.9f +- %.3ei | slopetui k=%.9g diff %.2e rel %.1e (from curve point %.2e away in tau)\n',...
        tt,ok,s.parameter(ip.k),s.period,cos(pi*w),abs(sin(pi*w)),ref(r,2),...
        s.parameter(ip.k)-ref(r,2),(s.parameter(ip.k)-ref(r,2))/ref(r,2),d);
end
fprintf('RUNTIME torus %s %.0fs\n',spec,toc(t0));
save('-mat',sprintf('torus_curve_%g_%g.mat',taulo,tauhi),'curve','sols','tau','k','T','om');
end
