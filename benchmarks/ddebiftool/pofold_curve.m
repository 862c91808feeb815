function pofold_curve(tau_lo,tau_hi,degree,intervals)
%% The fold of cycles as a curve in (k, tau): SetupPOfold with free (k, tau, c)
% from the fold at tau = 10 (found as in fold_tau.m), continued down to tau_lo
% and up to tau_hi. Then single POfold points corrected at exactly
% tau = 2, 5, 10, 20 from the nearest curve point (tau fixed, k free), and,
% at the low end, the distance of the curve to the Hopf curve.
if nargin<1, tau_lo=2; end
if nargin<2, tau_hi=20; end
if nargin<3, degree=4; end
if nargin<4, intervals=60; end
setup_path();
t0=tic;
tau0=10;
fprintf('collocation: degree %d, %d intervals (adaptive mesh)\n',degree,intervals);
[~,~,funcs,ip,hbr]=hopf_point(tau0,5.5);
[pbr,suc]=SetupPsol(funcs,hbr,1,'contpar',[ip.k,ip.c],'degree',degree,...
    'intervals',intervals,'radius',1e-3,'max_bound',[ip.k,30],'min_bound',[ip.k,0.02]);
if ~suc, error('psol init failed'); end
pbr.method.continuation.plot=0;
pbr.method.point.extra_condition=1;
pbr.method.continuation.steplength_growth_factor=1.2;
pbr.method.point.adapt_mesh_after_correct=1;
pbr.method.point.adapt_mesh_before_correct=1;
pbr.parameter.max_step=[ip.k,0.3;0,0.6];
for it=1:30
    pbr=br_contn(funcs,pbr,10);
    k=orbit_measures(pbr.point,ip); [~,i]=min(k);
    if i<numel(k)-2 && k(end)>k(i)*1.05, break; end
end
[~,~,fine]=fold_refine(funcs,pbr,ip);
% (tau is free in this correction too, so the start point lies on the fold curve
% near, not at, tau0; its own tau is printed)
[kp,Tp,pfbr,pfuncs,sp]=pofold_point(funcs,fine,ip,'contpar',[ip.k,ip.tau,ip.c]);
if ~sp, error('POfold near tau=%g failed',tau0); end
fprintf('POFOLD start tau=%.8f k_fold=%.8f T_fold=%.8f (%.0fs)\n',...
    pfbr.point(1).parameter(ip.tau),kp,Tp,toc(t0));
pfbr.method.continuation.plot=0;
pfbr.method.point.adapt_mesh_after_correct=1;
pfbr.method.point.adapt_mesh_before_correct=1;
pfbr.method.continuation.steplength_growth_factor=1.2;
pfbr.parameter.min_bound=[ip.tau,tau_lo];
pfbr.parameter.max_bound=[ip.tau,tau_hi];
pfbr.parameter.max_step=[ip.tau,0.5;ip.k,0.5];
t1=tic; curve=[];
for dir=[-1,1]
    br=pfbr; br.point=pfbr.point(1);
    p2=br.point(1); p2.parameter(ip.tau)=tau0+dir*0.02;
    p2.parameter(pfuncs.ip.ext_tau)=tau0+dir*0.02;   % the null vector's copy of tau
    [p2,ok]=p_correc(pfuncs,p2,setdiff(br.parameter.free,ip.tau),[],br.method.point);
    if ~ok, error('second POfold point failed'); end
    br.point(2)=p2;
    br=br_contn(pfuncs,br,200);
    pts=br.point; if dir<0, pts=fliplr(pts); end
    if isempty(curve), curve=pts; else, curve=[curve(1:end-1),pts(2:end)]; end %#ok<AGROW>
    fprintf('POFOLDCURVE leg %+d: %d points, %.0fs\n',dir,numel(br.point),toc(t1));
end
tcurve=toc(t1);
sols=arrayfun(@(p)pfuncs.get_comp(p,'solution'),curve);
tau=arrayfun(@(p)p.parameter(ip.tau),sols); [tau,o]=sort(tau); curve=curve(o); sols=sols(o);
k=arrayfun(@(p)p.parameter(ip.k),sols); T=[sols.period];
[~,~,A]=orbit_measures(sols,ip);
for i=1:numel(curve)
    fprintf('POFOLDCURVE tau=%.6f k=%.8f T=%.8f pp(m_y)=%.4e\n',tau(i),k(i),T(i),A(i));
end
fprintf('POFOLDCURVE %d points, tau in [%.4g, %.4g], runtime of the curve %.0fs (machine shared)\n',...
    numel(curve),tau(1),tau(end),tcurve);
%% single POfold points at exactly these tau, from the nearest curve point
for tt=unique([2,5,10,20,tau_lo])
    if tt<tau(1)-1e-9 || tt>tau(end)+1e-9, continue; end
    [d,j]=min(abs(tau-tt));
    pt=curve(j); pt.parameter([ip.tau,pfuncs.ip.ext_tau])=tt;
    [pt,ok]=p_correc(pfuncs,pt,setdiff(pfbr.parameter.free,ip.tau),[],pfbr.method.point);
    s=pfuncs.get_comp(pt,'solution');
    fprintf('POFOLD tau=%g success=%d k_fold=%.8f T_fold=%.8f (from curve point at distance %.2e in tau)\n',...
        tt,ok,s.parameter(ip.k),s.period,d);
end
fprintf('RUNTIME pofold_curve %.0fs\n',toc(t0));
save('-mat',sprintf('pofold_curve_%g_%g.mat',tau_lo,tau_hi),'curve','sols','tau','k','T','A');
end
